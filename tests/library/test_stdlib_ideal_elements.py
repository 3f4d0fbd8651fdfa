"""ElectricalComponents' ideal elements (Analog.Ideal) against closed forms; model
tests/models/Stdlib/IdealElements.dyad."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled


@pytest.fixture(scope="module")
def run():
    return Compiled().run("IdealElements", 2.0, points=401)


def test_ideal_transformer_divides_the_voltage_and_passes_the_power(run):
    # n = 4, 10 V on the primary, 5 ohm on the secondary
    np.testing.assert_allclose(run["transformer.v2"], 2.5, rtol=1e-12)
    np.testing.assert_allclose(run["transformer.i2"], -0.5, rtol=1e-12)
    np.testing.assert_allclose(run["transformer.i1"], 0.125, rtol=1e-12)
    np.testing.assert_allclose(run["transformer.v1"] * run["transformer.i1"]
                               + run["transformer.v2"] * run["transformer.i2"], 0, atol=1e-12)


def test_opening_switch_conducts_through_ron_then_goff(run):
    t, i = run.time, run["opener.i"]
    closed, opened = t < 0.99, t > 1.01
    np.testing.assert_allclose(i[closed], 10 / (10 + 1e-5), rtol=1e-10)
    # open: 10 V across Goff in series with 10 ohm
    np.testing.assert_allclose(i[opened], 10 / (10 + 1 / 1e-5), rtol=1e-10)


def test_closing_switch_charges_the_capacitor_from_its_closing(run):
    t = run.time
    tau = (1 + 1e-5) * 0.1
    expected = np.where(t < 0.5, 0.0, 10 * (1 - np.exp(-(t - 0.5) / tau)))
    np.testing.assert_allclose(run["c_charge.v"], expected, atol=1e-6)
    np.testing.assert_allclose(run["closer.i"][t < 0.49], 0.0, atol=0)
