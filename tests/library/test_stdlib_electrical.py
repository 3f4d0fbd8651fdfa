"""ElectricalComponents against closed-form circuit solutions (models in tests/models/Stdlib/)."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from tests.library.stdlib_support import Compiled


@pytest.fixture(scope="module")
def models():
    return Compiled()


def test_rc_charging_follows_the_exponential(models):
    # v_C = V (1 - exp(-t / RC)), i = (V / R) exp(-t / RC), with V = 10, R = 100, C = 1e-3.
    res = models.run("RCCharging", 0.5)
    t, tau = res.time, 100 * 1e-3
    np.testing.assert_allclose(res["capacitor.v"], 10 * (1 - np.exp(-t / tau)), atol=1e-7)
    np.testing.assert_allclose(res["voltmeter.v"], 10 * (1 - np.exp(-t / tau)), atol=1e-7)
    np.testing.assert_allclose(res["probe.phi"], 10 * (1 - np.exp(-t / tau)), atol=1e-7)
    np.testing.assert_allclose(res["ammeter.i"], 0.1 * np.exp(-t / tau), atol=1e-9)
    np.testing.assert_allclose(res["resistor.v"], 10 * np.exp(-t / tau), atol=1e-7)


def test_rc_charging_scales_with_tunable_parameters(models):
    # Twice the resistance doubles the time constant; no recompilation.
    res = models.run("RCCharging", 0.5, params={"resistor.R": 200, "source.V": 3})
    np.testing.assert_allclose(res["capacitor.v"], 3 * (1 - np.exp(-res.time / 0.2)), atol=1e-7)


def test_rl_circuit_current_rises_after_the_step(models):
    # i = 0 before t0 = 0.2; after: i = (V / R)(1 - exp(-(t - t0) R / L)), V = 5, R = 2, L = 0.5.
    res = models.run("RLStep", 1.5)
    t = res.time
    expected = np.where(t >= 0.2, 2.5 * (1 - np.exp(-(t - 0.2) * 2 / 0.5)), 0.0)
    np.testing.assert_allclose(res["inductor.i"], expected, atol=1e-7)
    np.testing.assert_allclose(res["inductor.v"], np.where(t >= 0.2, 5 - 2 * expected, 0.0), atol=1e-6)


def test_lc_oscillator_has_the_period_2_pi_sqrt_lc(models):
    # v = cos(w t), i = -C dv/dt... with the capacitor current i_C = C dv/dt = -i_L:
    # i_L = C w sin(w t), w = 1 / sqrt(L C) = 10 rad/s; after one period both return.
    w = 1 / math.sqrt(0.5 * 0.02)
    period = 2 * math.pi / w
    res = models.run("LCOscillator", period, points=401)
    t = res.time
    np.testing.assert_allclose(res["capacitor.v"], np.cos(w * t), atol=1e-6)
    np.testing.assert_allclose(res["inductor.i"], 0.02 * w * np.sin(w * t), atol=1e-6)
    assert res["capacitor.v"][-1] == pytest.approx(1.0, abs=1e-6)
    energy = 0.5 * 0.02 * res["capacitor.v"] ** 2 + 0.5 * 0.5 * res["inductor.i"] ** 2
    np.testing.assert_allclose(energy, 0.01, atol=1e-8)


def _away_from(t, instants, margin):
    """Mask of the times farther than `margin` from every switching instant."""
    return np.all(np.abs(t[:, None] - np.asarray(instants)[None, :]) > margin, axis=1)


def test_sine_sources_and_signal_driven_sources(models):
    res = models.run("ElectricalSources", 1.0, points=1001)
    t = res.time
    # Sine voltage across 4 Ohm: v = 1 + 2 sin(2 pi 5 (t - 0.1) + 0.3) from 0.1 s, 1 before.
    v = np.where(t >= 0.1, 1 + 2 * np.sin(2 * math.pi * 5 * (t - 0.1) + 0.3), 1.0)
    np.testing.assert_allclose(res["r_sine.v"], v, atol=1e-9)
    np.testing.assert_allclose(res["r_sine.i"], v / 4, atol=1e-9)
    # Sine current 0.5 sin(4 pi t) from n to p outside the source: through the resistor p -> n.
    np.testing.assert_allclose(res["r_sine_i.v"], 3 * 0.5 * np.sin(4 * math.pi * t), atol=1e-9)
    # Constant current 0.2 A into 0.5 F: v = 0.4 t.
    np.testing.assert_allclose(res["c_const.v"], 0.4 * t, atol=1e-8)
    # Current step 0.1 A, plus 2 A from 0.3 s, into 1.5 Ohm.
    np.testing.assert_allclose(res["r_step.v"], 1.5 * np.where(t >= 0.3, 2.1, 0.1), atol=1e-9)
    # Ramp 0 -> 4 over [0.2, 0.7] s, times 2 V, across a 0.25 S conductor.
    ramp = np.clip((t - 0.2) / 0.5, 0, 1) * 4
    np.testing.assert_allclose(res["r_signal_v.v"], 2 * ramp, atol=1e-9)
    np.testing.assert_allclose(res["r_signal_v.i"], 0.5 * ramp, atol=1e-9)
    # Constant 0.3 A from the signal-driven current source through 10 Ohm.
    np.testing.assert_allclose(res["r_signal_i.v"], 3.0, atol=1e-9)


def test_pulse_sources_between_and_across_their_edges(models):
    # Every edge is a time event (the pulse is written with floor alone), so the charge of the
    # capacitor is exact across edges; a sample that falls exactly on an edge may show either side.
    res = models.run("ElectricalSources", 1.0, points=1001)
    t = res.time
    phase = (t - 0.05) % 0.2
    v = np.where((t >= 0.05) & (phase < 0.06), 3.5, 0.5)
    edges = [0.05 + 0.2 * k for k in range(6)] + [0.11 + 0.2 * k for k in range(6)]
    keep = _away_from(t, edges, 1e-9)
    assert keep.sum() > 990
    np.testing.assert_allclose(res["r_pulse.v"][keep], v[keep], atol=1e-9)
    # Pulse current 1 A for the first half of every 0.25 s into 0.1 F: the charge grows by
    # 1 * 0.125 per period, linearly while high, flat while low.
    k, within = np.floor(t / 0.25), t % 0.25
    charge = 0.125 * k + np.minimum(within, 0.125)
    np.testing.assert_allclose(res["c_pulse.v"], charge / 0.1, atol=1e-7)


def _smooth_diode_current(v, ron=0.01, goff=1e-4, vknee=0.6, vsmooth=0.01):
    x = v - vknee
    r = math.sqrt(x * x + vsmooth * vsmooth)
    return goff * v + (1 / ron - goff) * ((x + r) / 2 - vsmooth**2 / (4 * r))


@pytest.mark.parametrize("source_v", [5.0, -5.0])
def test_diode_conducts_forward_and_blocks_reverse(models, source_v):
    res = models.run("DiodeCircuit", 0.1, points=3, params={"source.V": source_v})
    # The loop: source_v = R i + v_d with i = diode(v_d); solved here by bisection.
    v_d = brentq(lambda v: source_v - 10 * _smooth_diode_current(v) - v, -10, 10, xtol=1e-14)
    i = _smooth_diode_current(v_d)
    assert res["diode.v"][-1] == pytest.approx(v_d, abs=1e-8)
    assert res["diode.i"][-1] == pytest.approx(i, rel=1e-7)
    if source_v > 0:
        # Forward: the ideal two-segment diode gives (V - Vknee) / (R + Ron); the smoothing moves
        # the knee by less than Vsmooth, which changes the current by less than Vsmooth / R.
        assert abs(i - (5 - 0.6) / 10.01) < 0.01 / 10
    else:
        # Reverse: only the off conductance conducts (the rounding adds Vsmooth^4/(16 |x|^3) / Ron).
        assert i == pytest.approx(-5 * 1e-4 / (1 + 10 * 1e-4), rel=1e-6)
