"""The numerical state choice: which dummy derivatives a pivoting (Gram–Schmidt) choice takes at a
point, and how far the current choice is from being replaced, as a function IDAS can watch.

A monitored level (model.state_sets) is {"rows", "candidates", "chosen", "classes", "entries"}: the
level's Jacobian (rows x candidates, row-major) is the model's outputs `entries`; `chosen` are the
candidate positions that are dummy derivatives now.
"""
from __future__ import annotations

from typing import Mapping, Sequence

import casadi as ca
import numpy as np

SWITCH_RATIO = 0.5       # switch when swapping one chosen column for another gains a factor 2
_PIVOT_REL_TOL = 1e-8


def pivoted_columns(matrix: np.ndarray, classes: Sequence[Sequence[int]], n_rows: int,
                    rel_tol: float = _PIVOT_REL_TOL, folds: Sequence[Sequence[int]] = ()) -> list[int]:
    """Pivoted Gram–Schmidt: within each priority class (in order) take the column with the largest
    part orthogonal to the columns already chosen, until `n_rows` are chosen. This is the
    numerical dummy-derivative choice of the compiler, also made again where a run switches.

    `folds`: (row, u, w) alias rows of the level (compiler/structure/state_selection/folds.py): u is always
    taken, the choice is made without the rows and the w columns, and w is taken with u where
    that choice takes u."""
    matrix = np.asarray(matrix, dtype=float)
    scale = max(1.0, float(np.abs(matrix).max())) if matrix.size else 1.0
    if folds:
        return _folded_choice(matrix, classes, rel_tol * scale, folds)
    return _pivoted(matrix, classes, n_rows, rel_tol * scale)


def _folded_choice(matrix, classes, threshold, folds) -> list[int]:
    fold_rows = {int(r) for r, _, _ in folds}
    partner = {int(u): int(w) for _, u, w in folds}
    keep_rows = [i for i in range(matrix.shape[0]) if i not in fold_rows]
    keep_cols = [j for j in range(matrix.shape[1]) if j not in set(partner.values())]
    at = {j: k for k, j in enumerate(keep_cols)}
    sub_classes = [[at[j] for j in members if j in at] for members in classes]
    picked = [keep_cols[k] for k in _pivoted(matrix.take(keep_rows, axis=0).take(keep_cols, axis=1),
                                             [c for c in sub_classes if c], len(keep_rows), threshold)]
    if len(picked) < len(keep_rows):
        return picked                         # no regular choice: fewer than n_rows columns
    return list(partner) + [partner[j] for j in picked if j in partner] + \
        [j for j in picked if j not in partner]


def _pivoted(matrix: np.ndarray, classes, n_rows: int, threshold: float) -> list[int]:
    if n_rows == 0:
        return []
    if matrix.shape[0] == 1:
        # one constraint row (a pendulum rod): the largest entry of the first usable class
        row = np.abs(matrix[0]).tolist()
        for members in classes:
            if members:
                j = max(members, key=lambda k: row[k])
                if row[j] > threshold:
                    return [j]
        return []
    basis = np.zeros((matrix.shape[0], 0))
    chosen: list[int] = []
    for members in classes:
        remaining = list(members)
        while remaining and len(chosen) < n_rows:
            # all remaining columns at once (a 32-body chain: 0.8 instead of 6 ms per choice);
            # the first of equal norms wins, as in a loop over the class in order
            columns = matrix[:, remaining]
            residual = columns - basis @ (basis.T @ columns) if basis.shape[1] else columns
            norms = np.sqrt(np.einsum("ij,ij->j", residual, residual))
            k = int(norms.argmax())
            if not norms[k] > threshold:
                break
            basis = np.concatenate([basis, (residual[:, k] / norms[k])[:, None]], axis=1)
            chosen.append(remaining.pop(k))
        if len(chosen) == n_rows:
            break
    return chosen


def level_matrix(level: Mapping, outputs_column) -> np.ndarray:
    rows, n_cand = int(level["rows"]), len(level["candidates"])
    return np.asarray(outputs_column, dtype=float)[level["entries"]].reshape(rows, n_cand)


def state_selection_quality(state_sets: Sequence[Mapping], column: np.ndarray) -> tuple[float, int]:
    """min over the monitored levels of sigma_min(chosen block) / sigma_min(block that pivoting
    would choose here), 1 where the choice is the best one; and the worst level's index."""
    quality, worst = 1.0, -1
    for k, level in enumerate(state_sets):
        matrix = level_matrix(level, column)
        rows = int(level["rows"])
        best = pivoted_columns(matrix, level["classes"], rows)
        current = list(level["chosen"])
        if sorted(best) == sorted(current) or len(best) < rows:
            continue
        best_sigma = _smallest_singular(matrix[:, best])
        if best_sigma > 0:
            ratio = _smallest_singular(matrix[:, current]) / best_sigma
            if ratio < quality:
                quality, worst = ratio, k
    return quality, worst


def degraded_level(state_sets: Sequence[Mapping], column: np.ndarray) -> int | None:
    """The monitored level whose chosen pivot block has degraded at the point whose outputs are
    `column` (its quality below SWITCH_RATIO: the switch is taken there); None where it serves."""
    quality, level = state_selection_quality(state_sets, column)
    return level if quality < SWITCH_RATIO and level >= 0 else None


def _smallest_singular(block: np.ndarray) -> float:
    if not block.size:
        return 0.0
    if min(block.shape) == 1:                  # one row or column (a pendulum's rod): its length
        return float(np.sqrt(np.dot(block.ravel(), block.ravel())))
    return float(np.linalg.svd(block, compute_uv=False)[-1])


def switch_indicators(state_sets: Sequence[Mapping], outputs: ca.SX) -> ca.SX:
    """One function per monitored level that IDAS watches on its own steps: positive while the
    chosen dummy derivatives hold, crossing zero where exchanging one chosen column for another
    would multiply the pivot block's determinant by 1 / SWITCH_RATIO or more.

    By Cramer's rule, exchanging chosen column c for candidate j scales det(B) by |(B^-1 a_j)_c|;
    so the indicator is 1 - SWITCH_RATIO * max |B^-1 A_other|. The exchange back then gains at most
    SWITCH_RATIO, so a switch is never undone at once (hysteresis for free)."""
    indicators = []
    for level in state_sets:
        rows, n_cand = int(level["rows"]), len(level["candidates"])
        entries = outputs[[int(e) for e in level["entries"]]]
        matrix = ca.reshape(entries, n_cand, rows).T            # row-major entries
        chosen = list(level["chosen"])
        others = [j for j in range(n_cand) if j not in chosen]
        if not others:
            continue
        block = matrix[:, chosen]
        ratios = ca.solve(block, matrix[:, others]) if rows > 1 else matrix[:, others] / block
        indicators.append(1 - SWITCH_RATIO * ca.mmax(ca.fabs(ratios)))
    return ca.vertcat(*indicators) if indicators else ca.SX(0, 1)
