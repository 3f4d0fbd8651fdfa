"""Contender: Robertson's kinetics (DAE) with scipy's solve_ivp.

scipy has no DAE solver, so a Python user eliminates the algebraic equation
(y3 = 1 - y1 - y2) and integrates the remaining 2-state ODE with its analytic Jacobian.
Output on a logarithmic grid up to t = 1e11; error is the max relative deviation of
(y1, y2, y3) at 1e11 from the Test Set reference (tests/reference/robertson.py).
"""
from __future__ import annotations

import sys
import time as _time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _reference_loader import load_reference  # noqa: E402
from _result import contender_result  # noqa: E402


def run(method: str, rtol: float, atol: float, *, points: int = 161) -> dict:
    rob = load_reference("robertson")
    t_eval = np.concatenate([[0.0], np.logspace(-5, np.log10(rob.REFERENCE_T), points - 1)])
    start = _time.perf_counter()
    t, y, sol = rob.solve_reduced(t_eval, method=method, rtol=rtol, atol=atol,
                                  jac=method in ("Radau", "BDF", "LSODA"))
    wall = _time.perf_counter() - start
    if not sol.success:
        raise RuntimeError(f"{method} failed: {sol.message}")
    error = float(np.max(np.abs(y[:, -1] - rob.REFERENCE_Y) / rob.REFERENCE_Y))
    signals = {"y1": y[0], "y2": y[1], "y3": y[2]}
    stats = {"nfev": sol.nfev, "njev": sol.njev, "nlu": sol.nlu}
    return contender_result("robertson", method, rtol, atol, t, signals, wall, stats, error=error)


if __name__ == "__main__":
    res = run(sys.argv[1] if len(sys.argv) > 1 else "Radau", 1e-8, 1e-14)
    print(f"{res['method']}: {res['wall_time_s']:.3f} s, nfev {res['nfev']}, rel error at 1e11 {res['error']:.2e}")
