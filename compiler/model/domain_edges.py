"""When a value that must stay inside its domain (a divisor, a square root's or logarithm's
argument, the factor of a derivative, a pivot) leaves it or is about to, along a run towards a
failure (run_failures.py, singular_blocks.py)."""
from __future__ import annotations

import math

import numpy as np

# A value that must stay away from 0 (a divisor, a sqrt/log argument, a factor) counts as
# reaching it when it shrank to NEAR_SIZE of its largest size along the run and a straight line
# through its last two points reaches 0 within NEAR_EDGE of the time run so far.
NEAR_EDGE = 1e-2
NEAR_SIZE = 0.1


def domain_edge(kind: str, times: np.ndarray, series: np.ndarray) -> tuple[float | None, int]:
    """How soon `series` leaves its domain: negative when it already has (at index k), else the
    time its last trend needs to reach 0 as a fraction of the span run; None when it stays well
    inside."""
    if not np.isfinite(series).all():
        k = int(np.argmax(~np.isfinite(series)))
        return -2.0 + k / len(series), k
    outside = np.zeros(len(series), dtype=bool)
    if kind == "asin":
        outside = np.abs(series) > 1
    elif kind in ("sqrt", "log"):
        outside = (series < 0) | ((series == 0) & (kind == "log"))
    elif kind in ("divisor", "coefficient"):
        outside = series == 0
    if outside.any():
        k = int(np.argmax(outside))
        return -1.0 + k / len(series), k
    if kind == "asin" or len(series) < 2:
        return None, 0
    k = len(series) - 1
    size = float(np.max(np.abs(series)))
    last, before = float(series[k]), float(series[k - 1])
    step = times[k] - times[k - 1]
    if size == 0 or step <= 0 or abs(last) >= abs(before) or abs(last) > NEAR_SIZE * size:
        return None, 0
    # a straight line through the last two points: where it reaches 0, after the span run so far
    reach = abs(last) * step / abs(last - before)
    run = times[k] - times[0]
    relative = reach / run if run > 0 else math.inf
    return (relative, k) if relative < NEAR_EDGE else (None, 0)
