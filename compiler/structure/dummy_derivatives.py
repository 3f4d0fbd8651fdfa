"""Dummy derivatives (Mattsson–Söderlind 1993): choose which derivatives become algebraic.

Level by level, from the most-differentiated equations down: the rows are the equations obtained by
differentiation, the columns the candidate derivatives; pick as many independent columns as rows.
Independent column sets form a matroid (structurally: transversal; numerically: linear), so a
greedy pass in order of preference picks a best basis. Preference: a derivative of a variable
with a LOW state priority becomes a dummy first (so hinted variables stay states); within one
priority class, the numerically largest remaining column (pivoting) when a point is given.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from compiler.runtime import pivoted_columns
from compiler.structure.indexed import IndexedSystem


@dataclass
class DummySelection:
    dummies: list[int]                       # derivative unknowns made algebraic
    states: list[int]                        # unknowns integrated as states
    levels: list[tuple[list[int], list[int], list[int]]] = field(default_factory=list)  # (rows, candidates, chosen)
    deficient: bool = False                  # a level had fewer independent columns than rows
    pivot_conditions: list[float] = field(default_factory=list)   # per level, when numeric


def base_variable(system: IndexedSystem, v: int, diff_to_var: list[int]) -> int:
    while diff_to_var[v] >= 0:
        v = diff_to_var[v]
    return v


def select_dummy_derivatives(system: IndexedSystem, priority: Callable[[int], int],
                             jacobian: Callable[[list[int], list[int]], np.ndarray] | None = None,
                             ) -> DummySelection:
    """`priority(v)` is the state priority of unknown v's base variable; `jacobian(rows, cols)`
    evaluates d(equations[rows])/d(unknowns[cols]) at a point (None: structural choice only)."""
    diff_to_eq = system.diff_to_eq()
    diff_to_var = system.diff_to_var()
    rows = [e for e in range(system.n_eqs) if diff_to_eq[e] >= 0 and system.eq_to_diff[e] < 0]
    candidates = sorted({v for e in rows for v in system.incidence[e]
                         if system.var_to_diff[v] < 0 and diff_to_var[v] >= 0})
    selection = DummySelection([], [])
    while rows:
        chosen, condition = _choose_columns(system, rows, candidates, priority, jacobian)
        selection.levels.append((list(rows), list(candidates), list(chosen)))
        if condition is not None:
            selection.pivot_conditions.append(condition)
        if len(chosen) < len(rows):
            selection.deficient = True
        selection.dummies.extend(chosen)
        rows = [diff_to_eq[e] for e in rows if diff_to_eq[diff_to_eq[e]] >= 0]
        occurring = {v for e in rows for v in system.incidence[e]}
        candidates = sorted(diff_to_var[v] for v in chosen if diff_to_var[diff_to_var[v]] >= 0)
        candidates = [v for v in candidates if v in occurring]
    dummy_set = set(selection.dummies)
    selection.states = [v for v in range(system.n_vars)
                        if system.var_to_diff[v] >= 0 and system.var_to_diff[v] not in dummy_set]
    return selection


def _choose_columns(system, rows, candidates, priority, jacobian):
    row_index = {e: i for i, e in enumerate(rows)}
    column_rows = {v: [] for v in candidates}
    for e in rows:
        for v in system.incidence[e]:
            if v in column_rows:
                column_rows[v].append(row_index[e])
    # ties: rather make der(der(phi)) a dummy than der(w), so that named variables stay states
    order = sorted(candidates, key=lambda v: (priority(v), -system.names[v].count("der("), system.names[v]))
    values = jacobian(rows, order) if jacobian is not None else None
    if values is None:
        return _structural_greedy(order, column_rows, len(rows)), None
    return _numeric_greedy(order, values, priority, len(rows))


def _structural_greedy(order, column_rows, n_rows):
    """Add columns in order while a matching covering all chosen columns exists (augmenting paths)."""
    row_to_col: dict[int, int] = {}
    chosen = []
    for col in order:
        if len(chosen) == n_rows:
            break
        if _augment(col, column_rows, row_to_col, set()):
            chosen.append(col)
    return chosen


def _augment(col, column_rows, row_to_col, visited) -> bool:
    stack = [(col, iter(column_rows[col]))]
    path = []
    while stack:
        c, rows = stack[-1]
        advanced = False
        for r in rows:
            if r in visited:
                continue
            visited.add(r)
            if r not in row_to_col:
                path.append((c, r))
                for cc, rr in path:
                    row_to_col[rr] = cc
                return True
            path.append((c, r))
            stack.append((row_to_col[r], iter(column_rows[row_to_col[r]])))
            advanced = True
            break
        if not advanced:
            stack.pop()
            if path:
                path.pop()
    return False


def _numeric_greedy(order, values: np.ndarray, priority, n_rows, rel_tol=1e-8):
    """Pivoted Gram–Schmidt (runtime.pivoted_columns) over `order`, whose priority classes are
    consecutive runs. Returns (chosen, conditioning of the chosen block)."""
    classes: list[list[int]] = []
    for i, item in enumerate(order):
        if i == 0 or priority(item) != priority(order[i - 1]):
            classes.append([])
        classes[-1].append(i)
    chosen_positions = pivoted_columns(values, classes, n_rows, rel_tol)
    block = values[:, chosen_positions] if chosen_positions else np.zeros((values.shape[0], 0))
    cond = float(np.linalg.cond(block)) if block.shape[0] == block.shape[1] and block.size else float("inf")
    return [order[i] for i in chosen_positions], cond
