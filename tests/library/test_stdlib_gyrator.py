"""ElectricalComponents.Analog.Ideal.IdealGyrator against its gyration law, its power balance and
the inductor a capacitor becomes behind it; model tests/models/Stdlib/GyratorCircuits.dyad."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled


@pytest.fixture(scope="module")
def run():
    return Compiled().run("GyratorCircuits", 1.0, points=201)


def test_resistor_behind_the_gyrator_follows_the_gyration_law(run):
    # v1 = 2 V, G = 2 S, R = 5 ohm: i2 = -G v1 = -4 A drives v2 = 20 V, and i1 = G v2 = 40 A
    np.testing.assert_allclose(run["gyrator.v1"], 2.0, rtol=1e-12)
    np.testing.assert_allclose(run["gyrator.i2"], -4.0, rtol=1e-12)
    np.testing.assert_allclose(run["gyrator.v2"], 20.0, rtol=1e-12)
    np.testing.assert_allclose(run["gyrator.i1"], 40.0, rtol=1e-12)


def test_gyrator_absorbs_no_power(run):
    for name in ("gyrator", "as_inductor"):
        power = (run[f"{name}.v1"] * run[f"{name}.i1"] + run[f"{name}.v2"] * run[f"{name}.i2"])
        np.testing.assert_allclose(power, 0.0, atol=1e-9)


def test_capacitor_behind_the_gyrator_acts_as_an_inductor(run):
    # L = C / G^2 = 0.125 H in series with 1 ohm: i1 = 2 (1 - exp(-t / 0.125))
    t = run.time
    np.testing.assert_allclose(run["as_inductor.i1"], 2 * (1 - np.exp(-t / 0.125)), atol=1e-7)
    np.testing.assert_allclose(run["as_inductor.v2"], run["as_inductor.i1"] / 2, rtol=1e-12)
