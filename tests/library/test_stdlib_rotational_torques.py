"""RotationalComponents' torque sources (Sources.ConstantTorque, TorqueStep, the speed-dependent
and sign torques, ConstantSpeed) against closed forms of a free inertia they turn; model
tests/models/Stdlib/RotationalTorques.dyad."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled


@pytest.fixture(scope="module")
def run():
    return Compiled().run("RotationalTorques", 2.0, points=401)


def test_constant_torque_and_torque_step_accelerate_uniformly(run):
    t = run.time
    np.testing.assert_allclose(run["j_drive.w"], 2 * t, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(run["drive.tau"], 2, rtol=1e-12)
    np.testing.assert_allclose(run["j_step.w"], np.where(t < 0.5, 0.5 * t, 0.25 + 2 * (t - 0.5)),
                               rtol=1e-8, atol=1e-10)
    np.testing.assert_allclose(run["step.support.tau"], -run["step.spline.tau"], rtol=1e-12)


def test_speed_dependent_torques(run):
    t = run.time
    np.testing.assert_allclose(run["j_linear_damper.w"], np.exp(-2 * t), rtol=1e-7)
    np.testing.assert_allclose(run["j_linear_one_way.w"], -np.exp(2 * t), rtol=1e-7)
    np.testing.assert_allclose(run["j_drag.w"], 1 / (1 + t), rtol=1e-7)
    np.testing.assert_allclose(run["j_quadratic_one_way.w"], -1 / (1 - t / 10), rtol=1e-7)


def test_sign_torques_brake_and_follow_their_smoothing(run):
    t = run.time
    expected = np.where(t < 0.9, 1 - t, 0.1 * np.exp(-(t - 0.9) / 0.1))
    np.testing.assert_allclose(run["j_brake_linear.w"], expected, rtol=1e-6, atol=1e-9)
    w = run["j_brake_exp.w"]
    np.testing.assert_allclose(run["brake_exp.tau"], -(2 / (1 + np.exp(-w / 0.001)) - 1), atol=1e-9)
    w = run["j_brake_sine.w"]
    np.testing.assert_allclose(run["brake_sine.tau"],
                               -np.where(np.abs(w) >= 0.1, np.sign(w), np.sin(np.pi / 2 * w / 0.1)),
                               atol=1e-9)
    w = run["j_brake_cosine.w"]
    np.testing.assert_allclose(run["brake_cosine.tau"], -np.sign(w) * np.where(
        np.abs(w) >= 0.1, 1, 1 - np.cos(np.pi / 2 * w / 0.1)), atol=1e-9)


def test_constant_speed_turns_its_spline_uniformly(run):
    np.testing.assert_allclose(run["j_spinner.phi"], 2 * run.time, rtol=1e-9, atol=1e-12)


def test_torque2_turns_two_inertias_apart_without_net_momentum(run):
    t = run.time
    np.testing.assert_allclose(run["j_twist_a.w"], -1.5 * t, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(run["j_twist_b.w"], 1.5 * t / 2, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(1 * run["j_twist_a.w"] + 2 * run["j_twist_b.w"], 0, atol=1e-9)
