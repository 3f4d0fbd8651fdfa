"""Dummy derivatives (Mattsson–Söderlind 1993): choose which derivatives become algebraic.

Level by level, from the most-differentiated equations down: the rows are the equations obtained by
differentiation, the columns the candidate derivatives; pick as many independent columns as rows.
Independent column sets form a matroid (structurally: transversal; numerically: linear), so a
greedy pass in order of preference picks a best basis. Preference (runtime.selection_rules,
shared with the run-time choice): a derivative of a variable with a LOW state priority
(state_priority: the declared one, lowered for variables only the index reduction differentiates)
becomes a dummy first (so hinted variables stay states); within one priority class, the
numerically largest remaining column (pivoting) when a point is given.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Mapping

import numpy as np

from compiler.runtime.selection_rules import level_choice, preference_order
from compiler.structure.graph.matching import augmenting_path
from compiler.structure.indexed import IndexedSystem


@dataclass
class DummySelection:
    dummies: list[int]                       # derivative unknowns made algebraic
    states: list[int]                        # unknowns integrated as states
    levels: list[tuple[list[int], list[int], list[int]]] = field(default_factory=list)  # (rows, candidates, chosen)
    deficient: bool = False                  # a level had fewer independent columns than rows
    pivot_conditions: list[float] = field(default_factory=list)   # per level, when numeric

    @property
    def numeric(self) -> bool:
        """Whether every level was chosen by pivoting (not by names, for want of finite values)."""
        return len(self.pivot_conditions) == len(self.levels)


def base_variable(system: IndexedSystem, v: int, diff_to_var: list[int]) -> int:
    while diff_to_var[v] >= 0:
        v = diff_to_var[v]
    return v


def declared_priority(system: IndexedSystem, priorities: Mapping[str, int]) -> Callable[[int], int]:
    """The state priority declared for an unknown's base variable (0 where none is)."""
    diff_to_var = system.diff_to_var()

    def priority(v: int) -> int:
        return priorities.get(system.names[base_variable(system, v, diff_to_var)], 0)
    return priority


def state_priority(system: IndexedSystem, priorities: Mapping[str, int]) -> Callable[[int], int]:
    """The state priority of a candidate, as the compiler's choice, the run-time choice and the
    list of state sets order it: twice the declared priority of its base variable, less one where
    the model never differentiates that variable (der(g) only appears in equations the index
    reduction differentiated, g = f(y) say): between equal declared priorities its derivative is
    rather a dummy, and the variables the model differentiates stay states. So an auxiliary
    named for part of a constraint (`aux = d[2]^2` inside `L = sqrt(d[1]^2 + aux)`) does not
    take the place of the position the model integrates."""
    diff_to_var = system.diff_to_var()
    diff_to_eq = system.diff_to_eq()
    # the base variable: `der(der(x))` written in the model differentiates x (not only der(x))
    differentiated = {base_variable(system, d, diff_to_var) for e in range(system.n_eqs) if diff_to_eq[e] < 0
                      for d in system.incidence[e] if diff_to_var[d] >= 0}
    declared = declared_priority(system, priorities)

    def priority(v: int) -> int:
        return 2 * declared(v) - (0 if base_variable(system, v, diff_to_var) in differentiated else 1)
    return priority


def first_level(system: IndexedSystem) -> tuple[list[int], list[int]]:
    """The first level's rows (the most-differentiated equations obtained by differentiation)
    and its candidates (the highest derivatives they contain), both ascending."""
    diff_to_eq = system.diff_to_eq()
    diff_to_var = system.diff_to_var()
    rows = [e for e in range(system.n_eqs) if diff_to_eq[e] >= 0 and system.eq_to_diff[e] < 0]
    candidates = sorted({v for e in rows for v in system.incidence[e]
                         if system.var_to_diff[v] < 0 and diff_to_var[v] >= 0})
    return rows, candidates


def next_rows(system: IndexedSystem, rows: list[int]) -> list[int]:
    """The next level's rows: the equations `rows` were differentiated from, where those are
    themselves differentiated ones."""
    diff_to_eq = system.diff_to_eq()
    return [diff_to_eq[e] for e in rows if diff_to_eq[diff_to_eq[e]] >= 0]


def candidate_order(system: IndexedSystem, candidates, priority: Callable[[int], int]) -> list[int]:
    """`candidates` in the choice's order of preference (selection_rules.preference_order)."""
    return preference_order(candidates, priority, system.names.__getitem__)


def select_dummy_derivatives(system: IndexedSystem, priority: Callable[[int], int],
                             jacobian: Callable[[list[int], list[int]], np.ndarray] | None = None,
                             ) -> DummySelection:
    """`priority(v)` is the state priority of unknown v's base variable; `jacobian(rows, cols)`
    evaluates d(equations[rows])/d(unknowns[cols]) at a point (None: structural choice only)."""
    diff_to_var = system.diff_to_var()
    rows, candidates = first_level(system)
    selection = DummySelection([], [])
    while rows:
        chosen, condition = _choose_columns(system, rows, candidates, priority, jacobian)
        selection.levels.append((list(rows), list(candidates), list(chosen)))
        if condition is not None:
            selection.pivot_conditions.append(condition)
        if len(chosen) < len(rows):
            selection.deficient = True
        selection.dummies.extend(chosen)
        rows = next_rows(system, rows)
        occurring = {v for e in rows for v in system.incidence[e]}
        candidates = sorted(diff_to_var[v] for v in chosen if diff_to_var[diff_to_var[v]] >= 0)
        candidates = [v for v in candidates if v in occurring]
    dummy_set = set(selection.dummies)
    selection.states = [v for v in range(system.n_vars)
                        if system.var_to_diff[v] >= 0 and system.var_to_diff[v] not in dummy_set]
    return selection


def _choose_columns(system, rows, candidates, priority, jacobian):
    order = candidate_order(system, candidates, priority)
    values = jacobian(rows, order) if jacobian is not None else None
    if values is None:
        return structural_greedy(system, rows, order), None
    return _numeric_greedy(order, values, priority, len(rows))


def structural_greedy(system: IndexedSystem, rows: list[int], order: list[int]) -> list[int]:
    """The columns of `order` taken in order while the rows can be matched to all taken ones
    (an augmenting path per column: structure/graph/matching.py)."""
    position = {v: j for j, v in enumerate(order)}
    rows_of: list[list[int]] = [[] for _ in order]          # column position -> row positions
    for i, e in enumerate(rows):
        for v in system.incidence[e]:
            if v in position:
                rows_of[position[v]].append(i)
    column_to_row, row_to_column = [-1] * len(order), [-1] * len(rows)
    chosen = []
    for j, column in enumerate(order):
        if len(chosen) == len(rows):
            break
        if augmenting_path(j, rows_of, column_to_row, row_to_column)[0]:
            chosen.append(column)
    return chosen


def _numeric_greedy(order, values: np.ndarray, priority, n_rows):
    """Pivoted Gram–Schmidt over `order` (selection_rules.level_choice). Returns (chosen,
    conditioning of the chosen block)."""
    chosen_positions = level_choice(values, [priority(v) for v in order], n_rows)
    block = values[:, chosen_positions] if chosen_positions else np.zeros((values.shape[0], 0))
    cond = float(np.linalg.cond(block)) if block.size and block.shape[0] == block.shape[1] else float("inf")
    return [order[i] for i in chosen_positions], cond
