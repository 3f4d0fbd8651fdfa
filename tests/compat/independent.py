"""Independent values of the published test cases that dyadc and the published metadata disagree
on (issue 17): closed forms (sympy), exact piecewise integrals and small scipy integrations written
from each case's stated parameters, start values and stop time, without dyadc."""
from __future__ import annotations

from functools import lru_cache

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.linalg import expm, solve

_t = sp.Symbol("t", real=True)
_HALF = sp.Rational(1, 2)


def integral_of_started_signal(after: sp.Expr, start, before, stop) -> float:
    """x(stop) for x' = u, x(0) = 0, u = `before` up to `start` and `after` (in t) from it on."""
    return float(before * start + sp.integrate(after, (_t, start, stop)))


def clock_integral() -> float:
    return integral_of_started_signal(1 + _t - _HALF, _HALF, 1, 5)


def sine_integral() -> float:
    return integral_of_started_signal(_HALF + sp.sin(4 * sp.pi * (_t - _HALF) + sp.Rational(157, 100)),
                                      _HALF, _HALF, 5)


def cosine_integral() -> float:
    return integral_of_started_signal(_HALF + sp.cos(4 * sp.pi * (_t - _HALF) + sp.Rational(314, 100)),
                                      _HALF, _HALF, 5)


def damped_sine_integral() -> float:
    wave = sp.exp(-(_t - _HALF) / 2) * sp.sin(4 * sp.pi * (_t - _HALF) + sp.Rational(314, 100))
    return integral_of_started_signal(_HALF + wave, _HALF, _HALF, 7)


def ramp_integral() -> float:
    rising = sp.integrate(_HALF + (_t - _HALF) / sp.Rational(7, 10), (_t, _HALF, sp.Rational(6, 5)))
    return float(_HALF * _HALF + rising + sp.Rational(3, 2) * (3 - sp.Rational(6, 5)))


def single_pulse_integral() -> float:
    # 0.75 everywhere on [0, 3] plus (1.5 - 0.75) on the pulse (0.5, 0.5 + 0.5 * 0.75]
    return float(sp.Rational(3, 4) * 3 + sp.Rational(3, 4) * sp.Rational(3, 8))


def piecewise_linear_integral(shape, start: float, stop: float, period: float, before: float,
                              pieces: int = 4) -> float:
    """x(stop) for u = `before` up to `start`, then shape(phase in [0, 1)) of a wave of `period`
    that is linear on each of `pieces` equal parts of a period: the midpoint rule over those
    parts is exact (and never evaluates the wave at its jumps)."""
    edges = np.arange(start, stop + 1e-12, period / pieces)
    total = before * start
    for a, b in zip(edges[:-1], edges[1:]):
        total += shape((0.5 * (a + b) - start) / period % 1.0) * (b - a)
    return total


def square_integral() -> float:
    return piecewise_linear_integral(lambda s: 0.7 + (1.0 if s < 0.5 else -1.0), 0.5, 5.0, 0.5, 0.7, 2)


def triangle_integral() -> float:
    def triangle(s):
        return 4 * s if s <= 0.25 else (2 - 4 * s if s <= 0.75 else 4 * s - 4)
    return piecewise_linear_integral(triangle, 0.5, 5.0, 0.5, 0.7)


def limiter_at_one() -> float:
    """clamp(x(1), -3, 3) for x' = 4 pi sin(2 pi t), x(0) = 0."""
    x = sp.integrate(4 * sp.pi * sp.sin(2 * sp.pi * _t), (_t, 0, 1))
    return float(sp.Min(sp.Max(x, -3), 3))


@lru_cache(maxsize=None)
def slew_limited_at_one(td: float = 1e-3) -> tuple[float, float]:
    """y(1) for y' = clamp((u - y) / td, -1, 1), u = 2 sin(4 pi t), y(0) = u(0) = 0: integrated one
    regime at a time (rising at 1, falling at -1, or following u) with the switching instants
    located as events, and once through all switches with Radau; both results."""
    def u(t):
        return 2 * np.sin(4 * np.pi * t)

    def mode_at(t, y):
        rate = (u(t) - y) / td
        return 1.0 if rate > 1 else -1.0 if rate < -1 else 0.0

    t, y = 0.0, 0.0
    while t < 1.0:
        mode = mode_at(t + 1e-12, y)
        rhs = (lambda s, v: [(u(s) - v[0]) / td]) if mode == 0.0 else (lambda s, v, m=mode: [m])
        events = []
        for level in (1.0, -1.0):
            def event(s, v, level=level):
                return (u(s) - v[0]) / td - level
            event.terminal = True
            events.append(event)
        sol = solve_ivp(rhs, (t, 1.0), [y], method="Radau" if mode == 0.0 else "DOP853",
                        rtol=1e-12, atol=1e-14, events=events)
        if sol.t[-1] - t < 1e-12:           # an event at the piece's start: step just past it
            sol = solve_ivp(rhs, (t, min(1.0, t + 1e-9)), [y], method="DOP853", rtol=1e-12, atol=1e-14)
        t, y = float(sol.t[-1]), float(sol.y[0, -1])
    through = solve_ivp(lambda s, v: [np.clip((u(s) - v[0]) / td, -1.0, 1.0)], (0.0, 1.0), [0.0],
                        method="Radau", rtol=1e-12, atol=1e-14, max_step=1e-4)
    return y, float(through.y[0, -1])


def double_integrator_collector() -> float:
    """2 a + 3 v + 4 x at t = 10 for a = sin(10 pi t) integrated twice from rest."""
    a = sp.sin(10 * sp.pi * _t)
    v = sp.integrate(a, (_t, 0, _t))
    x = sp.integrate(v, (_t, 0, _t))
    return float((2 * a + 3 * v + 4 * x).subs(_t, 10))


def linear_sine_response(a, b, x0, omega: float, amplitude: float, offset: float, stop: float):
    """x(stop) for x' = A x + b (offset + amplitude sin(omega t)), x(0) = x0, in closed form: the
    steady response (a phasor for the sine, -A^-1 b for the offset) plus exp(A t) times the start's
    deviation from it; and the same from a DOP853 integration at rtol 1e-13."""
    a, b, x0 = (np.asarray(v, dtype=float) for v in (a, b, x0))
    phasor = solve(1j * omega * np.eye(len(b)) - a, b)
    level = -solve(a, b) * offset

    def steady(t):
        return amplitude * np.imag(phasor * np.exp(1j * omega * t)) + level
    closed = steady(stop) + expm(a * stop) @ (x0 - steady(0.0))
    ode = solve_ivp(lambda t, x: a @ x + b * (offset + amplitude * np.sin(omega * t)), (0.0, stop),
                    x0, method="DOP853", rtol=1e-13, atol=1e-15).y[:, -1]
    return closed, ode


def rc_sensors(x_of=0) -> dict[str, float]:
    """1 Ohm, 1 F, source 1 + 10 sin(10 pi t), capacitor from 10 V, at t = 20: v' = (V - v) / RC."""
    closed, ode = linear_sine_response([[-1.0]], [1.0], [10.0], 10 * np.pi, 10.0, 1.0, 20.0)
    v = (closed, ode)[x_of][0]
    source = 1 + 10 * np.sin(10 * np.pi * 20.0)
    current = source - v
    return {"i": current, "v": v, "power": v * current}


def parallel_glc(x_of=0) -> dict[str, float]:
    """State (capacitor voltage, inductor current) with C v' = -I - i_L - G v, L i_L' = v,
    I = sin(2 pi t), both 0 at t = 0, at t = 10."""
    g = 0.1
    v, i_l = linear_sine_response([[-g, -1.0], [1.0, 0.0]], [-1.0, 0.0], [0.0, 0.0], 2 * np.pi,
                                  1.0, 0.0, 10.0)[x_of]
    return {"capacitor.i": -np.sin(2 * np.pi * 10.0) - i_l - g * v, "inductor.i": i_l,
            "v": v}


def sine_rlc(x_of=0) -> float:
    """Capacitor voltage at t = 10 with C v' = -i_L - v / R, L i_L' = v - sin(2 pi t),
    v(0) = 10, i_L(0) = 0, R = 100, C = 1 mF, L = 1."""
    r, c = 100.0, 1e-3
    v, _ = linear_sine_response([[-1 / (r * c), -1 / c], [1.0, 0.0]], [0.0, -1.0], [10.0, 0.0],
                                2 * np.pi, 1.0, 0.0, 10.0)[x_of]
    return v
