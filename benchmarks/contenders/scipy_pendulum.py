"""Contender: the planar pendulum (point mass on a rigid rod) with scipy's solve_ivp.

A Python user writes the angle ODE theta'' = -(g/L) sin(theta) directly (with its exact
Jacobian for the implicit methods). The error is the max-norm deviation of theta from the
closed form in tests/reference/pendulum.py. Defaults: m = 1, L = 1, g = 9.80665,
theta0 = 1.2 rad from the downward vertical, released from rest, 10 s, 1001 points.
"""
from __future__ import annotations

import sys
import time as _time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _reference_loader import load_reference  # noqa: E402
from _result import contender_result  # noqa: E402


def run(method: str, rtol: float, atol: float, *, m: float = 1.0, L: float = 1.0, g: float = 9.80665,
        theta0: float = 1.2, t_end: float = 10.0, points: int = 1001) -> dict:
    pend = load_reference("pendulum")
    t_eval = np.linspace(0.0, t_end, points)
    start = _time.perf_counter()
    sol = pend.solve_numerically(t_eval, L=L, theta0=theta0, g=g, method=method, rtol=rtol, atol=atol,
                                 jac=method in ("Radau", "BDF", "LSODA"))
    wall = _time.perf_counter() - start
    if not sol.success:
        raise RuntimeError(f"{method} failed: {sol.message}")
    theta, omega = sol.y
    exact = pend.solution(sol.t, m=m, L=L, theta0=theta0, g=g)
    signals = {
        "theta": theta, "omega": omega, "x": L * np.sin(theta), "y": -L * np.cos(theta),
        "tension": m * (L * omega ** 2 + g * np.cos(theta)),
    }
    stats = {"nfev": sol.nfev, "njev": sol.njev, "nlu": sol.nlu}
    return contender_result("pendulum", method, rtol, atol, sol.t, signals, wall, stats,
                            error=float(np.max(np.abs(theta - exact["theta"]))))


if __name__ == "__main__":
    res = run(sys.argv[1] if len(sys.argv) > 1 else "Radau", 1e-8, 1e-8)
    print(f"{res['method']}: {res['wall_time_s']:.3f} s, nfev {res['nfev']}, max theta error {res['error']:.2e}")
