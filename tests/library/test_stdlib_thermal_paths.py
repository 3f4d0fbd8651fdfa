"""ThermalComponents under both of Dyad's namings against closed forms and a conservation law:
the HeatPort components of the documented sub-packages (Components, Sources, Sensors; model
tests/models/Stdlib/ThermalConvection.dyad) and the flat paths of Dyad's earlier library with
Node connectors and heat flows named Q (tests/models/Stdlib/ThermalNodes.dyad)."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled

SIGMA = 5.670374419e-8


@pytest.fixture(scope="module")
def ports():
    return Compiled().run("ThermalConvection", 10.0)


@pytest.fixture(scope="module")
def nodes():
    return Compiled().run("ThermalNodes", 10.0)


def test_convection_cools_exponentially(ports):
    # C dT/dt = -Gc (T - 300), T(0) = 350, Gc / C = 0.2
    excess = 50 * np.exp(-0.2 * ports.time)
    np.testing.assert_allclose(ports["body1.T"], 300 + excess, atol=1e-7)
    np.testing.assert_allclose(ports["excess.T_rel"], excess, atol=1e-7)
    np.testing.assert_allclose(ports["convection.ΔT"], excess, atol=1e-7)
    np.testing.assert_allclose(ports["convection.Q_flow"], 4 * excess, atol=1e-6)


def test_convective_resistor_cools_exponentially(ports):
    # dT/dt = -(T - 300) / (Rc C), 1 / (Rc C) = 0.4
    np.testing.assert_allclose(ports["body2.T"], 300 + 10 * np.exp(-0.4 * ports.time), atol=1e-7)


def test_temperature_dependent_heat_flow(ports):
    # C dθ/dt = Q (1 + alpha θ), θ = T - T_ref, θ(0) = 0: θ = (exp(alpha Q t / C) - 1) / alpha
    theta = 100 * (np.exp(0.01 * ports.time) - 1)
    np.testing.assert_allclose(ports["body3.T"], 300 + theta, atol=1e-7)
    np.testing.assert_allclose(ports["body4.T"], 300 + theta, atol=1e-7)


def test_radiation_conserves_heat_and_follows_stefan_boltzmann(ports):
    hot, cold = ports["hot.T"], ports["cold.T"]
    np.testing.assert_allclose(3 * hot + 2 * cold, 3 * 600 + 2 * 300, rtol=1e-10)
    np.testing.assert_allclose(ports["radiation.Q_flow"], 0.01 * SIGMA * (hot ** 4 - cold ** 4),
                               rtol=1e-8)
    assert hot[-1] < 600 and cold[-1] > 300


def test_flat_nodes_cool_heat_and_follow_like_the_ports(nodes):
    t = nodes.time
    cooled = 300 + 100 * np.exp(-0.05 * t)
    np.testing.assert_allclose(nodes["body1.T"], cooled, atol=1e-7)
    np.testing.assert_allclose(nodes["body2.T"], cooled, atol=1e-7)
    np.testing.assert_allclose(nodes["thermometer.T"], cooled, atol=1e-7)
    np.testing.assert_allclose(nodes["excess.T_rel"], cooled - 300, atol=1e-7)
    np.testing.assert_allclose(nodes["heat_meter.Q"], 5 * (cooled - 300), atol=1e-6)
    np.testing.assert_allclose(nodes["conductor.Q"], 5 * (cooled - 300), atol=1e-6)
    np.testing.assert_allclose(nodes["conductor.ΔT"], cooled - 300, atol=1e-7)
    np.testing.assert_allclose(nodes["body1.dT"], -0.05 * (cooled - 300), atol=1e-8)
    theta = 100 * (np.exp(0.01 * t) - 1)
    np.testing.assert_allclose(nodes["body3.T"], 300 + theta, atol=1e-7)
    np.testing.assert_allclose(nodes["body4.T"], 300 + theta, atol=1e-7)
    k = 0.25
    np.testing.assert_allclose(nodes["body5.T"], 300 + 5 * t - 5 / k * (1 - np.exp(-k * t)), atol=1e-7)


def test_flat_convection_resistor_and_radiation(nodes):
    t = nodes.time
    np.testing.assert_allclose(nodes["body6.T"], 300 + 50 * np.exp(-0.2 * t), atol=1e-7)
    np.testing.assert_allclose(nodes["body7.T"], 300 + 10 * np.exp(-0.4 * t), atol=1e-7)
    hot, cold = nodes["hot.T"], nodes["cold.T"]
    np.testing.assert_allclose(3 * hot + 2 * cold, 3 * 600 + 2 * 300, rtol=1e-10)
    np.testing.assert_allclose(nodes["radiation.Q"], 0.01 * SIGMA * (hot ** 4 - cold ** 4), rtol=1e-8)
