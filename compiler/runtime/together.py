"""Several watched rows that change sign between the same two check times (sampled_idas.py): the
crossing the run stops at is the earliest of them, and rows that cross at that same instant are
listed with it. Locating only the first row by row order lost the others: the next call starts
past them (issue 32: the detailed op-amp's `q_sum < ...` crossed 4 ns before the `q_sum > ...`
that was located, and was never listed; rem's floor jumps where rem's relation flips)."""
from __future__ import annotations

import numpy as np

from .crossings import ROOT_TOLERANCE, locate
from .watches import Watch


def earliest_crossing(add, integrator, watch: Watch, row: int, t_left: float, t_right: float,
                      x_left, z_left, p, ignored=frozenset()):
    """(t, x, z, crossed, row, together): `row`'s crossing in (t_left, t_right] located
    (crossings.locate), replaced by any other event row's that lies earlier by more than the root
    tolerance; `together` the event rows, other than the one returned, that have crossed by then
    too (at the same instant within the tolerance), in row order, as (row, direction)."""
    t, x, z, crossed = locate(add, integrator, watch, row, t_left, t_right, x_left, z_left, p)
    if not crossed:
        return t, x, z, False, row, ()
    before = _values(watch, x_left, z_left, p, t_left)
    rivals = [i for i, (kind, _) in enumerate(watch.labels)
              if kind == "event" and i not in ignored and np.isfinite(before[i])]
    for _ in range(len(rivals) + 1):
        passed = _passed(watch, rivals, row, before, x, z, p, t)
        earlier = None
        for i in passed:
            t_i, x_i, z_i, crossed_i = locate(add, integrator, watch, i, t_left, t, x_left, z_left, p)
            if crossed_i and t_i < t - 2.0 * ROOT_TOLERANCE * max(1.0, abs(t)) \
                    and (earlier is None or t_i < earlier[0]):
                earlier = (t_i, x_i, z_i, i)
        if earlier is None:
            together = tuple((i, 1 if before[i] <= 0 else -1) for i in passed)
            return t, x, z, True, row, together
        t, x, z, row = earlier
    return t, x, z, True, row, ()


def _passed(watch: Watch, rivals, row: int, before, x, z, p, t) -> list[int]:
    """The rows of `rivals` (but `row`) whose sign at (t, x, z) is not their sign at the start."""
    at = _values(watch, x, z, p, t)
    return [i for i in rivals if i != row and (before[i] > 0) != (at[i] > 0)]


def _values(watch: Watch, x, z, p, t) -> np.ndarray:
    return np.asarray(watch.values(np.asarray(x).reshape(-1, 1), np.asarray(z).reshape(-1, 1),
                                   p, [t]))[:, 0]
