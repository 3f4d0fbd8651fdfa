"""The filtered references of Translational and Rotational Position, Speed and VelocitySource
(Dyad's default `ref_type`) against the step responses of their filters; model
tests/models/Stdlib/MotionFilters.dyad."""
from __future__ import annotations

import math

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled

A_F, B_F = 1.3617, 0.6180


@pytest.fixture(scope="module")
def run():
    return Compiled().run("MotionFilters", 2.0, points=401)


def _bessel_step(t, f_crit):
    """Response from rest of b/w^2 s'' + a/w s' + s = 1 (complex poles sigma +- i omega)."""
    w = 2 * math.pi * f_crit
    sigma = -A_F * w / (2 * B_F)
    omega = math.sqrt(w ** 2 / B_F - sigma ** 2)
    return 1 - np.exp(sigma * t) * (np.cos(omega * t) - sigma / omega * np.sin(omega * t))


def test_filtered_position_sources_follow_the_bessel_step_response(run):
    expected = _bessel_step(run.time, 1.0)
    np.testing.assert_allclose(run["carriage.s"], expected, atol=1e-7)
    np.testing.assert_allclose(run["wheel.phi"], expected, atol=1e-7)
    # the force that moves the carriage along the filtered path
    np.testing.assert_allclose(run["position.flange.f"], -2 * run["position.a"], rtol=1e-9, atol=1e-9)


def test_filtered_speed_sources_rise_exponentially(run):
    decay = np.exp(-2 * math.pi * 2 * run.time)
    np.testing.assert_allclose(run["slider.v"], 2 * (1 - decay), atol=1e-7)
    np.testing.assert_allclose(run["rotor.w"], 3 * (1 - decay), atol=1e-7)
