"""The common result record of every scipy contender's run()."""
from __future__ import annotations

import numpy as np


def contender_result(problem, method, rtol, atol, time, signals, wall_time_s, sol_stats, error=None):
    """Dict with the output grid, the named signals, their final values and solver statistics.

    keys: problem, method, rtol, atol, time (grid), signals {name: array on the grid},
    final {name: value at the last grid point}, wall_time_s (integration incl. output
    evaluation), nfev, njev, nlu, and error (max-norm deviation from the problem's published
    or closed-form reference, None when the problem has none).
    """
    return {
        "problem": problem, "method": method, "rtol": rtol, "atol": atol,
        "time": np.asarray(time, dtype=float),
        "signals": {k: np.asarray(v, dtype=float) for k, v in signals.items()},
        "final": {k: float(np.asarray(v)[-1]) for k, v in signals.items()},
        "wall_time_s": wall_time_s,
        "nfev": int(sol_stats.get("nfev", 0)), "njev": int(sol_stats.get("njev", 0)),
        "nlu": int(sol_stats.get("nlu", 0)),
        "error": error,
    }
