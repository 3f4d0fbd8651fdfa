"""PrescribeInitialEquilibrium and PrescribeInitialAcceleration (Rotational and Translational)
against the static balance and the oscillation they start; model
tests/models/Stdlib/MechanicsInitialization.dyad."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled


@pytest.fixture(scope="module")
def res():
    return Compiled().run("MechanicsInitialization", 2.0)


def test_equilibrium_start_stays_at_the_static_deflection(res):
    # 2 N.m on a 4 N.m/rad spring: 0.5 rad; 5 N on a 50 N/m spring: 0.1 m, for all t.
    np.testing.assert_allclose(res["inertia1.phi"], 0.5, atol=1e-9)
    np.testing.assert_allclose(res["mass1.s"], 0.1, atol=1e-9)


def test_prescribed_initial_acceleration_sets_the_initial_deflection(res):
    t = res.time
    # J a0 = -c phi0: phi0 = 0.5 * 2 / 8, then a free oscillation at sqrt(8 / 0.5) = 4 rad/s.
    np.testing.assert_allclose(res["inertia2.phi"], 0.125 * np.cos(4 * t), atol=1e-8)
    # m a0 = -c s0: s0 = -2 * 0.9 / 18, oscillating at sqrt(18 / 2) = 3 rad/s.
    np.testing.assert_allclose(res["mass2.s"], -0.1 * np.cos(3 * t), atol=1e-8)
