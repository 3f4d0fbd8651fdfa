"""ElectricalComponents' controlled sources (VCV, VCC, CCV, CCC) and Gyrator against their
defining laws in loaded circuits; model tests/models/Stdlib/ElectricalTwoPorts.dyad."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled


@pytest.fixture(scope="module")
def res():
    return Compiled().run("ElectricalTwoPorts", 1.0)


def test_voltage_controlled_sources(res):
    v1 = np.sin(2 * np.pi * res.time)
    np.testing.assert_allclose(res["vcv.v2"], 2 * v1, atol=1e-9)
    np.testing.assert_allclose(res["vcv.i1"], 0, atol=1e-12)
    np.testing.assert_allclose(res["vcv.i2"], -2 * v1 / 10, atol=1e-9)   # the load draws v2 / 10 out of p2
    np.testing.assert_allclose(res["vcc.i2"], 0.5 * v1, atol=1e-9)
    np.testing.assert_allclose(res["vcc.v2"], -4 * 0.5 * v1, atol=1e-9)  # i2 enters p2 from the load


def test_current_controlled_sources_short_their_control_port(res):
    i1 = np.sin(2 * np.pi * res.time) / 2          # the 2 ohm series resistor sets the current
    for source in ("ccv", "ccc"):
        np.testing.assert_allclose(res[f"{source}.v1"], 0, atol=1e-12)
        np.testing.assert_allclose(res[f"{source}.i1"], i1, atol=1e-9)
    np.testing.assert_allclose(res["ccv.v2"], 3 * i1, atol=1e-9)
    np.testing.assert_allclose(res["ccc.i2"], 4 * i1, atol=1e-9)


def test_gyrator_turns_its_capacitor_into_an_inductor_without_losing_power(res):
    # L = C / (G1 G2) = 0.4 H behind 2 ohm from 1 V: i1 = 0.5 (1 - exp(-5 t)).
    np.testing.assert_allclose(res["gyrator.i1"], 0.5 * (1 - np.exp(-5 * res.time)), atol=1e-8)
    power = res["gyrator.v1"] * res["gyrator.i1"] + res["gyrator.v2"] * res["gyrator.i2"]
    np.testing.assert_allclose(power, 0, atol=1e-12)
