"""Contender: the excavator dig cycle with scipy's solve_ivp on the hand-derived model.

The model is tests/reference/excavator_minimal.py (19 states in minimal coordinates, analytic
complex-step Jacobian). atol is scaled per state as spec section 5 asks (1 for angles, rates
and controller states, 1e7 for pressures, 100 for m_load). One solve_ivp call over [0, 12] s,
as a Python user would write it; split_at_waypoints=True restarts at the reference's
waypoints instead. There is no exact solution: error is None, compare against a tight run.
"""
from __future__ import annotations

import sys
import time as _time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _reference_loader import load_reference  # noqa: E402
from _result import contender_result  # noqa: E402


def run(method: str, rtol: float, atol: float, *, t_end: float = 12.0, points: int = 1201,
        split_at_waypoints: bool = False) -> dict:
    model = load_reference("excavator_minimal")
    t_eval = np.linspace(0.0, t_end, points)
    start = _time.perf_counter()
    out = model.simulate(t_eval, rtol=rtol, atol=atol, method=method, split_at_waypoints=split_at_waypoints)
    wall = _time.perf_counter() - start
    signals = {k: v for k, v in out.items() if k not in ("time", "_states", "nfev", "njev", "nlu")}
    return contender_result("excavator", method, rtol, atol, out["time"], signals, wall, out)


if __name__ == "__main__":
    res = run(sys.argv[1] if len(sys.argv) > 1 else "Radau", 1e-8, 1e-8)
    print(f"{res['method']}: {res['wall_time_s']:.2f} s, nfev {res['nfev']}, "
          f"m_load(12) = {res['final']['soil.m_load']:.6f} kg")
