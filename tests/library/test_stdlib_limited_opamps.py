"""ElectricalComponents' limited ideal op-amps as inverting amplifiers of gain -10 driven past
their limits: the output follows -10 u in between and sits at the limit outside, and the
inverting input leaves virtual ground only while limited (resistor divider); model
tests/models/Stdlib/LimitedOpAmps.dyad."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled

R_IN, R_FB = 1000.0, 10000.0


@pytest.fixture(scope="module")
def run():
    return Compiled().run("LimitedOpAmps", 1.0, points=601)


def divider(u, out):
    """Potential of the inverting input between the source u and the output out."""
    return (u * R_FB + out * R_IN) / (R_IN + R_FB)


def test_ideal_limited_output_is_linear_between_its_limits_and_clipped_outside(run):
    u = 2 * np.sin(2 * np.pi * run.time)
    expected = np.clip(-10 * u, -5.0, 8.0)
    assert np.count_nonzero(expected == 8.0) > 50 and np.count_nonzero(expected == -5.0) > 50
    np.testing.assert_allclose(run["amp.out.v"], expected, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(run["amp.in_n.v"], divider(u, expected), rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(run["amp.vin"], -divider(u, expected), rtol=1e-9, atol=1e-9)


def finite_gain_output(u, gain, low, high):
    """Output of the inverting amplifier on an op-amp of no-load gain `gain` clipped to
    [low, high]: the linear solution of out = -gain divider(u, out), clipped (out is monotone)."""
    linear = -gain * u * R_FB / (R_IN + R_FB + gain * R_IN)
    return np.clip(linear, low, high)


def test_idealized_output_follows_the_finite_gain_and_stops_at_the_supply(run):
    u = 8 * np.sin(2 * np.pi * run.time)
    expected = finite_gain_output(u, 15000.0, -15.0, 15.0)
    linear = np.abs(expected) < 15.0
    assert np.count_nonzero(linear) > 20 and np.count_nonzero(~linear) > 300
    np.testing.assert_allclose(run["idealized.v_out"], expected, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(run["idealized.vps"], 15.0, rtol=0)
    np.testing.assert_allclose(run["idealized.vns"], -15.0, rtol=0)


def test_idealized_on_supply_pins_clips_to_them_and_draws_the_output_power(run):
    u = 2 * np.sin(2 * np.pi * run.time)
    expected = finite_gain_output(u, 15000.0, -5.0, 8.0)
    assert np.count_nonzero(expected == 8.0) > 50 and np.count_nonzero(expected == -5.0) > 50
    np.testing.assert_allclose(run["supplied.v_out"], expected, rtol=1e-9, atol=1e-9)
    power = sum(run[f"supplied.{pin}.v"] * run[f"supplied.{pin}.i"]
                for pin in ("in_p", "in_n", "out", "s_p", "s_n"))
    np.testing.assert_allclose(power, 0.0, atol=1e-12)
    assert np.max(np.abs(run["supplied.s_p.i"])) > 1e-3
