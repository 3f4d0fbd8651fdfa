"""Alias rows of a level of the dummy-derivative choice, folded: where `der(x) = vx` was
differentiated, the level holds the row der(der(x)) - der(vx) = 0 and both der(der(x)) and der(vx)
as candidates. The choice (runtime.pivoted_columns with `folds`) always takes der(der(x)) and
makes the rest of the choice on the level without those rows and without the der(vx) columns, as
if vx had been eliminated as an alias of der(x); der(vx) is taken with der(der(x)) when the folded
choice takes der(der(x)), so that x and vx are states together or dummies together.

Without folding, pivoting over the whole level mixes the alias rows' unit entries into its
choice: a chain of bodies then ends up with a velocity state of one coordinate beside the position
state of another (vx1 with y1), and the levels' choices combine freely, which multiplies the state
sets a run can reach (656 structurally regular ones for a 3-body Cartesian chain).
"""
from __future__ import annotations

from typing import Sequence

import numpy as np
import sympy

from compiler.model.flat import TIME
from compiler.structure.differentiate import partial
from compiler.structure.indexed import IndexedSystem


def alias_folds(system: IndexedSystem, rows: Sequence[int], order: Sequence[int],
                priority) -> list[tuple[int, int, int]]:
    """(row position, u, w) for each row of `rows` with exactly two entries among the candidates
    `order`, u's and w's, both plain numbers (no symbol, so at every point and parameter value),
    where w has no other entry on the level, |u_r| >= |w_r|, and u is not behind w in the order
    of preference (an earlier priority class, or the same class and |u_r| > |w_r| or u first).
    A row written times a factor of parameters (`k * der(x) = k * vx`) folds as the row without
    it (row_pair): the choice may not depend on how an equation is scaled.
    Each column and row is in one fold at most."""
    position = {v: j for j, v in enumerate(order)}
    entries_of = {v: [] for v in order}
    for e in rows:
        for v in system.incidence[e]:
            if v in entries_of:
                entries_of[v].append(e)
    folds, used = [], set()
    for i, r in enumerate(rows):
        entries = sorted((v for v in system.incidence[r] if v in position), key=position.__getitem__)
        if len(entries) != 2:
            continue
        for u, w in (entries, entries[::-1]):
            if entries_of[w] != [r] or u in used or w in used:
                continue
            u_r, w_r = row_pair(system, r, u, w)
            if u_r is None or w_r is None or w_r == 0:
                continue
            pu, pw = priority(u), priority(w)
            if pu < pw or (pu == pw and (abs(u_r) > abs(w_r)
                                         or (abs(u_r) == abs(w_r) and position[u] < position[w]))):
                folds.append((i, u, w))
                used.update((u, w))
                break
    return folds


def plain_number(system: IndexedSystem, e: int, v: int) -> float | None:
    """d equation / d unknown where it is a plain finite number (no symbol at all), else None."""
    derivative = partial(system.equations[e], system.symbols[v])
    if derivative.free_symbols:
        return None
    try:
        value = float(derivative)
    except (TypeError, ValueError):
        return None
    return value if np.isfinite(value) else None


def row_pair(system: IndexedSystem, e: int, u: int, w: int) -> tuple[float | None, float | None]:
    """(d e / d u, d e / d w) as plain numbers, up to a common factor: the entries themselves where
    both are plain numbers, else (their ratio, 1) where the ratio is a plain finite number and w's
    entry depends on no unknown and not on time (a factor of parameters, which scales the whole
    equation); (None, None) otherwise."""
    u_r, w_r = plain_number(system, e, u), plain_number(system, e, w)
    if u_r is not None and w_r is not None:
        return u_r, w_r
    ratio = common_factor_ratio(system, system.equations[e], u, w)
    return (None, None) if ratio is None else (ratio, 1.0)


def common_factor_ratio(system: IndexedSystem, residual, u: int, w: int) -> float | None:
    """d residual / d u over d residual / d w where that is a plain finite number and the
    denominator holds no unknown and not time (it may hold parameters); else None."""
    du, dw = partial(residual, system.symbols[u]), partial(residual, system.symbols[w])
    if dw == 0 or any(s in system.index_of or s == TIME for s in dw.free_symbols):
        return None
    ratio = sympy.cancel(du / dw)
    if ratio.free_symbols:
        return None
    try:
        value = float(ratio)
    except (TypeError, ValueError):
        return None
    return value if np.isfinite(value) and value != 0 else None


def unfolded(chosen_folded: Sequence[int], folds: Sequence[tuple[int, int, int]]) -> list[int]:
    """The level's whole choice from the folded one: every u, the w of each u the folded choice
    takes, and the folded choice's other columns."""
    us = {u: w for _, u, w in folds}
    return [u for _, u, _ in folds] + [us[v] for v in chosen_folded if v in us] + \
        [v for v in chosen_folded if v not in us]
