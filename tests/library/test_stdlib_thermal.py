"""ThermalComponents against closed forms (Newton cooling, constant and sine heating, a body
following a temperature ramp); model in tests/models/Stdlib/ThermalSystems.dyad."""
from __future__ import annotations

import math

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled


@pytest.fixture(scope="module")
def thermal():
    return Compiled().run("ThermalSystems", 10.0)


def test_body_cools_exponentially_through_a_conductor(thermal):
    # C dT/dt = -G (T - 300), T(0) = 400: T = 300 + 100 exp(-G t / C), G / C = 0.05.
    t = thermal.time
    T = 300 + 100 * np.exp(-0.05 * t)
    np.testing.assert_allclose(thermal["body1.T"], T, atol=1e-7)
    np.testing.assert_allclose(thermal["thermometer.T"], T, atol=1e-7)
    np.testing.assert_allclose(thermal["heat_meter.Q_flow"], 5 * (T - 300), atol=1e-6)
    np.testing.assert_allclose(thermal["conductor.Q_flow"], 5 * (T - 300), atol=1e-6)
    np.testing.assert_allclose(thermal["body1.dT"], -0.05 * (T - 300), atol=1e-8)


def test_thermal_resistor_is_the_inverse_conductance(thermal):
    np.testing.assert_allclose(thermal["body2.T"], 300 + 100 * np.exp(-0.05 * thermal.time), atol=1e-7)


def test_heat_flow_sources_heat_bodies(thermal):
    t = thermal.time
    # 25 W into 50 J/K: T = 300 + 0.5 t.
    np.testing.assert_allclose(thermal["body3.T"], 300 + 0.5 * t, atol=1e-8)
    # 20 sin(2 pi 0.1 t) W into 10 J/K: T = 300 + 2 (1 - cos(w t)) / w, w = 0.2 pi.
    w = 2 * math.pi * 0.1
    np.testing.assert_allclose(thermal["body4.T"], 300 + 2 * (1 - np.cos(w * t)) / w, atol=1e-7)


def test_body_lags_a_temperature_ramp(thermal):
    # u = 300 + 5 t, C dT/dt = G (u - T), T(0) = 300, k = G / C = 0.25:
    # T = u - (5 / k)(1 - exp(-k t)).
    t, k = thermal.time, 0.25
    np.testing.assert_allclose(thermal["body5.T"], 300 + 5 * t - 5 / k * (1 - np.exp(-k * t)), atol=1e-7)
