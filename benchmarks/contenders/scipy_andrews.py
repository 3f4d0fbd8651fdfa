"""Contender: Andrews' squeezing mechanism with scipy's solve_ivp (index-1 ODE form).

The index-3 DAE is reduced by hand to an ODE for the 7 angles and 7 rates (accelerations and
multipliers from the KKT system each step; tests/reference/andrews.py), with a complex-step
Jacobian for the implicit methods. error is the max relative deviation of the 7 angles at
t = 0.03 from the Test Set reference.
"""
from __future__ import annotations

import sys
import time as _time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _reference_loader import load_reference  # noqa: E402
from _result import contender_result  # noqa: E402


def run(method: str, rtol: float, atol: float, *, points: int = 31) -> dict:
    andr = load_reference("andrews")
    t_eval = np.linspace(0.0, andr.T_END, points)
    start = _time.perf_counter()
    sol = andr.solve(t_eval, method=method, rtol=rtol, atol=atol)
    wall = _time.perf_counter() - start
    if not sol.success:
        raise RuntimeError(f"{method} failed: {sol.message}")
    angles = sol.y[:7, -1]
    error = float(np.max(np.abs(angles - andr.REFERENCE_ANGLES) / np.abs(andr.REFERENCE_ANGLES)))
    signals = {name: sol.y[i] for i, name in enumerate(andr.ANGLE_NAMES)}
    signals.update({f"der({name})": sol.y[7 + i] for i, name in enumerate(andr.ANGLE_NAMES)})
    stats = {"nfev": sol.nfev, "njev": sol.njev, "nlu": sol.nlu}
    return contender_result("andrews", method, rtol, atol, sol.t, signals, wall, stats, error=error)


if __name__ == "__main__":
    res = run(sys.argv[1] if len(sys.argv) > 1 else "Radau", 1e-8, 1e-8)
    print(f"{res['method']}: {res['wall_time_s']:.3f} s, nfev {res['nfev']}, angle rel error {res['error']:.2e}")
