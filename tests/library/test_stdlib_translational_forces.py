"""TranslationalComponents' force sources (Sources.ConstantForce, ForceStep, the speed-dependent
and sign forces, ConstantVelocity/ConstantSpeed) against closed forms of a free mass they push;
model tests/models/Stdlib/TranslationalForces.dyad."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled


@pytest.fixture(scope="module")
def run():
    return Compiled().run("TranslationalForces", 2.0, points=401)


def test_constant_force_and_force_step_accelerate_uniformly(run):
    t = run.time
    np.testing.assert_allclose(run["m_constant.v"], 2 * t, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(run["push.f"], -2, rtol=1e-12)
    before, after = t < 0.499, t > 0.501
    np.testing.assert_allclose(run["m_step.a"][before], 0.5, rtol=1e-9)
    np.testing.assert_allclose(run["m_step.a"][after], 2.0, rtol=1e-9)
    np.testing.assert_allclose(run["m_step.v"], np.where(t < 0.5, 0.5 * t, 0.25 + 2 * (t - 0.5)),
                               rtol=1e-8, atol=1e-10)
    # the housing takes the reaction
    np.testing.assert_allclose(run["step.support.f"], -run["step.flange.f"], rtol=1e-12)


def test_linear_speed_dependent_forces(run):
    t = run.time
    # turning with the motion, f_nominal < 0: a viscous damper, m v' = -2 v
    np.testing.assert_allclose(run["m_linear_damper.v"], np.exp(-2 * t), rtol=1e-7)
    # one direction whatever the motion: m v' = -2 |v| with v < 0 speeds the mass up
    np.testing.assert_allclose(run["m_linear_one_way.v"], -np.exp(2 * t), rtol=1e-7)


def test_quadratic_speed_dependent_forces(run):
    t = run.time
    np.testing.assert_allclose(run["m_drag.v"], 1 / (1 + t), rtol=1e-7)              # v' = -v|v|
    np.testing.assert_allclose(run["m_quadratic_one_way.v"], -1 / (1 - t / 10), rtol=1e-7)  # 10 v' = -v^2


def test_sign_force_with_linear_smoothing_brakes_then_decays(run):
    t, v = run.time, run["m_brake_linear.v"]
    expected = np.where(t < 0.9, 1 - t, 0.1 * np.exp(-(t - 0.9) / 0.1))
    np.testing.assert_allclose(v, expected, rtol=1e-6, atol=1e-9)


def test_sign_force_exp_sine_cosine_follow_their_laws(run):
    t = run.time
    np.testing.assert_allclose(run["m_brake_exp.v"][t < 0.8], 1 - t[t < 0.8], rtol=1e-8)
    v = run["m_brake_exp.v"]
    np.testing.assert_allclose(run["brake_exp.f"], 2 / (1 + np.exp(-v / 0.001)) - 1, atol=1e-9)
    v = run["m_brake_sine.v"]
    np.testing.assert_allclose(run["brake_sine.f"],
                               np.where(np.abs(v) >= 0.1, np.sign(v), np.sin(np.pi / 2 * v / 0.1)),
                               atol=1e-9)
    assert v[-1] > 0 and v[-1] < 0.1                    # came into the smoothed band, not through 0
    v = run["m_brake_cosine.v"]
    np.testing.assert_allclose(run["brake_cosine.f"], np.sign(v) * np.where(
        np.abs(v) >= 0.1, 1, 1 - np.cos(np.pi / 2 * v / 0.1)), atol=1e-9)


def test_constant_speed_moves_its_flange_uniformly(run):
    np.testing.assert_allclose(run["m_conveyor.s"], 2 * run.time, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(run["conveyor.f"], 0, atol=1e-9)        # a free mass needs no force
