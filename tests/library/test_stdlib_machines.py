"""ElectricalComponents' RotationalEMF, power and multi sensors, NonlinearResistor and
SaturatingInductor against closed forms and conservation laws; model
tests/models/Stdlib/ElectricalMachines.dyad."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled


@pytest.fixture(scope="module")
def res():
    return Compiled().run("ElectricalMachines", 3.0, points=3001)


def test_dc_motor_runs_up_to_supply_over_k(res):
    # J w' = k i, i = (V - k w) / R: w = V/k (1 - exp(-k^2 t / (R J))) = 20 (1 - exp(-1.25 t)).
    t = res.time
    w = 20 * (1 - np.exp(-1.25 * t))
    np.testing.assert_allclose(res["rotor.w"], w, atol=1e-7)
    np.testing.assert_allclose(res["emf.i"], (10 - 0.5 * w) / 2, atol=1e-7)


def test_emf_turns_electrical_power_into_mechanical_and_the_housing_takes_the_reaction(res):
    electrical = res["emf.v"] * res["emf.i"]
    mechanical = 0.1 * res["rotor.a"] * res["rotor.w"]
    np.testing.assert_allclose(electrical, mechanical, atol=1e-6)
    np.testing.assert_allclose(res["emf.housing.tau"], -res["emf.rotor.tau"], atol=1e-10)


def test_power_and_multi_sensors_measure_without_disturbing(res):
    i = res["emf.i"]
    np.testing.assert_allclose(res["armature_power.power"], 2 * i**2, atol=1e-7)
    np.testing.assert_allclose(res["emf_meter.i"], i, atol=1e-10)
    np.testing.assert_allclose(res["emf_meter.v"], res["emf.v"], atol=1e-10)
    np.testing.assert_allclose(res["emf_meter.power"], res["emf.v"] * i, atol=1e-8)


def test_chua_resistor_follows_its_three_segments(res):
    v = 3 * np.sin(2 * np.pi * res.time)
    expected = np.where(v < -1, 0.1 * (v + 1) - 0.5, np.where(v > 1, 0.1 * (v - 1) + 0.5, 0.5 * v))
    np.testing.assert_allclose(res["chua.v"], v, atol=1e-9)
    np.testing.assert_allclose(res["chua.i"], expected, atol=1e-9)


def test_saturating_inductor_flux_is_the_integral_of_its_voltage(res):
    t, i, psi = res.time, res["coil.i"], res["coil.psi"]
    # v = 1 - R i across the coil; psi(0) = 0.
    integral = np.concatenate([[0], np.cumsum(np.diff(t) * ((1 - i[1:]) + (1 - i[:-1])) / 2)])
    np.testing.assert_allclose(psi, integral, atol=1e-6)
    # Defaults: L_zero = 2 at rest, falling towards L_inf = 0.5 as the current grows.
    assert res["coil.L_actual"][0] == 2.0
    np.testing.assert_allclose(res["coil.L_actual"][1:], psi[1:] / i[1:], rtol=1e-9)
    assert np.all(np.diff(res["coil.L_actual"][1:]) < 0)
