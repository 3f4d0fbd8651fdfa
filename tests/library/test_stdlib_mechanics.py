"""TranslationalComponents and RotationalComponents against closed forms (damped oscillators,
constant-force motion, free fall, a gear train); models in tests/models/Stdlib/."""
from __future__ import annotations

import math

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled

G = 9.80665


@pytest.fixture(scope="module")
def models():
    return Compiled()


@pytest.fixture(scope="module")
def translational(models):
    return models.run("TranslationalSystems", 2.0)


@pytest.fixture(scope="module")
def rotational(models):
    return models.run("RotationalSystems", 3.0)


def damped(t, x0, m, c, d):
    """Free response x(t), v(t), a(t) of m x'' + d x' + c x = 0 from x0 at rest (underdamped)."""
    sigma, wd = d / (2 * m), math.sqrt(c / m - (d / (2 * m)) ** 2)
    x = x0 * np.exp(-sigma * t) * (np.cos(wd * t) + sigma / wd * np.sin(wd * t))
    v = -x0 * (sigma**2 + wd**2) / wd * np.exp(-sigma * t) * np.sin(wd * t)
    return x, v, -(c * x + d * v) / m


def test_mass_on_spring_and_damper_and_every_sensor(translational):
    res, t = translational, translational.time
    x, v, a = damped(t, 0.1, m=2, c=50, d=4)
    np.testing.assert_allclose(res["mass1.s"], x, atol=1e-8)
    np.testing.assert_allclose(res["position.s"], x, atol=1e-8)
    np.testing.assert_allclose(res["velocity.v"], v, atol=1e-7)
    np.testing.assert_allclose(res["acceleration.a"], a, atol=1e-6)
    # The sensor passes the spring and damper force on to the mass: f = m a = -(c x + d v).
    np.testing.assert_allclose(res["force_sensor.f"], 2 * a, atol=1e-6)
    np.testing.assert_allclose(res["spring.f"], 50 * x, atol=1e-7)


def test_spring_damper_oscillates_about_its_free_length(translational):
    x, _, _ = damped(translational.time, 0.1, m=2, c=50, d=4)
    np.testing.assert_allclose(translational["mass2.s"], 0.3 + x, atol=1e-8)


def test_force_sources_accelerate_masses_uniformly(translational):
    t = translational.time
    # 3 N on 1.5 kg: s = t^2; the 0.4 m long mass has its right flange at s + 0.2.
    np.testing.assert_allclose(translational["mass3.s"], t**2, atol=1e-8)
    np.testing.assert_allclose(translational["position3.s"], t**2 + 0.2, atol=1e-8)
    np.testing.assert_allclose(translational["mass3.a"], 2.0, atol=1e-7)
    # -1 N on 0.5 kg: s = -t^2.
    np.testing.assert_allclose(translational["mass4.s"], -t**2, atol=1e-8)


def test_mass_on_a_vertical_path_falls_freely(translational):
    # m (a + g sin(pi/2)) = 0: a = -g, s = 10 - g t^2 / 2.
    t = translational.time
    np.testing.assert_allclose(translational["mass5.s"], 10 - G * t**2 / 2, atol=1e-7)
    np.testing.assert_allclose(translational["mass5.a"], -G, atol=1e-7)


def test_inertia_on_torsion_spring_and_damper_and_every_sensor(rotational):
    # Three seconds of oscillation: the integrator's global error reaches a few 1e-8 rad.
    res, t = rotational, rotational.time
    phi, w, a = damped(t, 0.5, m=0.5, c=8, d=0.2)
    np.testing.assert_allclose(res["inertia1.phi"], phi, atol=2e-7)
    np.testing.assert_allclose(res["angle.phi"], phi, atol=2e-7)
    np.testing.assert_allclose(res["speed.w"], w, atol=5e-6)
    np.testing.assert_allclose(res["acceleration.a"], a, atol=5e-6)
    np.testing.assert_allclose(res["torque_sensor.tau"], 0.5 * a, atol=5e-6)


def test_rotational_spring_damper_oscillates_about_its_offset(rotational):
    phi, _, _ = damped(rotational.time, 0.5, m=0.5, c=8, d=0.2)
    np.testing.assert_allclose(rotational["inertia2.phi"], 0.1 + phi, atol=2e-7)


def test_ideal_gear_reflects_the_output_inertia_by_the_ratio_squared(rotational):
    # Torque 2 on J_a = 0.1, gear ratio n = 4 to J_b = 0.8: the input sees J_a + J_b / n^2 = 0.15,
    # so alpha_a = 2 / 0.15, alpha_b = alpha_a / n, and the gear passes J_b alpha_b to the load.
    t = rotational.time
    alpha_a = 2 / (0.1 + 0.8 / 16)
    np.testing.assert_allclose(rotational["inertia_a.phi"], alpha_a * t**2 / 2, atol=1e-7)
    np.testing.assert_allclose(rotational["inertia_b.phi"], alpha_a / 4 * t**2 / 2, atol=1e-7)
    np.testing.assert_allclose(rotational["inertia_a.phi"], 4 * rotational["inertia_b.phi"], atol=1e-9)
    np.testing.assert_allclose(rotational["output_torque.tau"], 0.8 * alpha_a / 4, atol=1e-7)


def test_torque_sources_with_and_without_support(rotational):
    t = rotational.time
    np.testing.assert_allclose(rotational["inertia_c.phi"], (2 / 2) * t**2 / 2, atol=1e-8)
    np.testing.assert_allclose(rotational["inertia_d.phi"], (-0.5 / 0.25) * t**2 / 2, atol=1e-8)
