"""BlockComponents against closed forms: sources, integrators, a filtered derivative, arithmetic,
lags, a limiter, and LimPID closing a loop around a first-order plant (with and without output
saturation); models in tests/models/Stdlib/."""
from __future__ import annotations

import math

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled


@pytest.fixture(scope="module")
def models():
    return Compiled()


@pytest.fixture(scope="module")
def blocks(models):
    return models.run("BlockSignals", 4.0, points=801)


def test_integrators_of_constant_step_and_pulse(blocks):
    t = blocks.time
    np.testing.assert_allclose(blocks["integrate_constant.y"], 1 + 1.5 * 2 * t, atol=1e-8)
    np.testing.assert_allclose(blocks["step.y"][t > 0.5 + 1e-9], 3.0)
    np.testing.assert_allclose(blocks["integrate_step.y"], t + 2 * np.maximum(t - 0.5, 0), atol=1e-8)
    # Pulse: -1 until 0.2, then per period of 0.4: +1 for 0.1, -1 for 0.3 (net -0.2 a period).
    tau = t - 0.2
    periods = np.floor(tau / 0.4 + 1e-9)                # whole periods (robust at the boundaries)
    r = np.maximum(tau - 0.4 * periods, 0)
    area = -0.2 + (-0.2 * periods + np.minimum(r, 0.1) - np.maximum(r - 0.1, 0))
    np.testing.assert_allclose(blocks["integrate_pulse.y"], np.where(t < 0.2, -t, area), atol=1e-7)


def test_filtered_derivative_of_a_ramp(blocks):
    # u = 0.5 + 1.5 (t - t0) on [t0, t0 + 2], t0 = 1.05; y = k s/(T s + 1) u with k = 2, T = 0.05:
    # 0 before t0, k 1.5 (1 - exp(-(t - t0)/T)) during the rise, then decaying as exp(-(t - t0 - 2)/T).
    # (The ramp's ends are kept off the pulse edges: two time events 4e-16 apart stop the run
    # with IDA_ILL_INPUT, a runtime issue reported separately.)
    t, k, T, t0 = blocks.time, 2.0, 0.05, 1.05
    rising = k * 1.5 * (1 - np.exp(-(t - t0) / T))
    falling = k * 1.5 * (1 - math.exp(-2 / T)) * np.exp(-(t - t0 - 2) / T)
    expected = np.where(t < t0, 0.0, np.where(t < t0 + 2, rising, falling))
    np.testing.assert_allclose(blocks["derivative.y"], expected, atol=1e-6)
    ramp = np.clip((t - t0) / 2, 0, 1) * 3 + 0.5
    np.testing.assert_allclose(blocks["ramp.y"], ramp, atol=1e-12)


def test_arithmetic_blocks_on_sine_and_cosine(blocks):
    t = blocks.time
    s = 1 + 2 * np.sin(math.pi * t + 0.2)
    c = 0.5 * np.cos(2 * math.pi * t)
    for name, expected in [("sine.y", s), ("cosine.y", c), ("gain.y", 3 * s), ("add.y", s - 2 * c),
                           ("add3.y", s + c + 1), ("feedback.y", s - c), ("product.y", s * c),
                           ("division.y", s / 2), ("limiter.y", np.clip(s, -0.5, 1.5))]:
        np.testing.assert_allclose(blocks[name], expected, atol=1e-9, err_msg=name)


def test_first_and_second_order_step_responses(blocks):
    t = blocks.time
    np.testing.assert_allclose(blocks["first_order.y"], 2.4 * (1 - np.exp(-t / 0.1)), atol=1e-8)
    # y'' + 2 d w y' + w^2 y = k w^2 u with u = 2, k = 0.5, w = 4, d = 0.3 (underdamped).
    d, w = 0.3, 4.0
    wd = w * math.sqrt(1 - d * d)
    y = 1 - np.exp(-d * w * t) * (np.cos(wd * t) + d / math.sqrt(1 - d * d) * np.sin(wd * t))
    np.testing.assert_allclose(blocks["second_order.y"], y, atol=1e-7)


def test_pi_controller_cancelling_the_plant_pole_gives_a_first_order_loop(models):
    # C = k (1 + 1/(Ti s)), P = 1/(T s + 1), Ti = T: C P = k/(T s), so y = 1 - exp(-k t / T),
    # and the controller output is u = T y' + y = 1 + (k - 1) exp(-k t / T), k = 4, T = 0.5.
    res = models.run("PIDLoop", 1.5)
    t = res.time
    np.testing.assert_allclose(res["plant.y"], 1 - np.exp(-8 * t), atol=1e-7)
    np.testing.assert_allclose(res["pid.y"], 1 + 3 * np.exp(-8 * t), atol=1e-6)
    np.testing.assert_allclose(res["pid.D"], 0.0, atol=1e-12)


def test_limited_pi_controller_saturates_and_its_integrator_tracks_the_limit(models):
    # Output limited to 2: while saturated the plant sees u = 2, y = 2 (1 - exp(-2 t)), and
    # the integrator follows Ti x' = e + (2 - v)/(k Ni), v = k (e + x), e = 1 - y = -1 + 2 exp(-2t):
    # x' = a x + b e + c with a = -1/(Ni Ti), b = (1 - 1/Ni)/Ti, c = 2/(k Ni Ti), x(0) = 0.
    res = models.run("PIDLoop", 1.5, points=1501, params={"pid.y_max": 2, "pid.y_min": -2})
    t = res.time
    k, Ti, Ni = 4.0, 0.5, 0.9
    a, b, c = -1 / (Ni * Ti), (1 - 1 / Ni) / Ti, 2 / (k * Ni * Ti)
    e = -1 + 2 * np.exp(-2 * t)
    x = (c - b) * (np.exp(a * t) - 1) / a + 2 * b * (np.exp(a * t) - np.exp(-2 * t)) / (a + 2)
    v = k * (e + x)
    saturated = np.cumprod(v > 2).astype(bool)         # up to the first time v reaches the limit
    t_release = t[saturated][-1]
    assert 0.1 < t_release < 1.4                        # it does saturate, and then recovers
    np.testing.assert_allclose(res["pid.y"][saturated], 2.0, atol=1e-9)
    np.testing.assert_allclose(res["plant.y"][saturated], 2 * (1 - np.exp(-2 * t[saturated])), atol=1e-7)
    np.testing.assert_allclose(res["pid.x_i"][saturated], x[saturated], atol=1e-7)
    np.testing.assert_allclose(res["pid.v"][saturated], v[saturated], atol=1e-6)
    # After the release the loop settles on the set-point.
    assert res["plant.y"][-1] == pytest.approx(1.0, abs=1e-3)
    assert np.all(res["pid.y"] <= 2 + 1e-9)
