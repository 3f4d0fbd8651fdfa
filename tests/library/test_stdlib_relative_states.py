"""RelativeStates (Rotational and Translational) and the rotational a_rel of
PartialCompliantWithRelativeStates: two free two-body oscillators started in relative
coordinates; model tests/models/Stdlib/RelativeStatesSystems.dyad."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled


@pytest.fixture(scope="module")
def res():
    return Compiled().run("RelativeStatesSystems", 2.0)


def test_relative_coordinates_oscillate_at_the_two_body_frequency(res):
    # c (1/J1 + 1/J2) = 6 * 1.5 = 9: the twist and the stretch run as 0.3 cos(3 t).
    t = res.time
    np.testing.assert_allclose(res["rel_r.phi_rel"], 0.3 * np.cos(3 * t), atol=1e-7)
    np.testing.assert_allclose(res["rel_r.a_rel"], -2.7 * np.cos(3 * t), atol=1e-6)
    np.testing.assert_allclose(res["rel_t.s_rel"], 0.3 * np.cos(3 * t), atol=1e-7)


def test_relative_states_transmit_nothing_so_momentum_is_conserved(res):
    # Started at rest: J1 phi1 + J2 phi2 and m1 s1 + m2 s2 keep their initial values.
    np.testing.assert_allclose(res["inertia1.phi"] + 2 * res["inertia2.phi"], 0.6, atol=1e-9)
    np.testing.assert_allclose(res["mass1.s"] + 2 * res["mass2.s"], 0.6, atol=1e-9)


def test_spring_damper_a_rel_is_its_inertias_acceleration(res):
    np.testing.assert_allclose(res["spring_damper.a_rel"], res["inertia3.a"], atol=1e-9)
