"""Coarse Dulmage–Mendelsohn decomposition: which equations and variables are over-, under- or
exactly determined. It names the culprits of a structurally singular system.

Given any maximum matching:
- overdetermined: everything reachable from an unmatched equation by alternating paths
  (equation -> any of its variables -> the equation matched to that variable);
- underdetermined: everything reachable from an unmatched variable by alternating paths
  (variable -> any equation containing it -> the variable matched to that equation);
- square: the rest (perfectly matched, and independent of the choice of maximum matching).
The partition is the same for every maximum matching.
"""
from __future__ import annotations

from dataclasses import dataclass

from compiler.structure.graph.matching import UNMATCHED, maximum_matching


@dataclass
class DMPartition:
    """Each equation and each variable lies in exactly one of the four groups of its kind.

    `unmatched_eqs` belong to the overdetermined part and `unmatched_vars` to the underdetermined
    part, but they are listed only there: the full overdetermined subsystem is
    (overdetermined_eqs + unmatched_eqs, overdetermined_vars); see `overdetermined_subsystem()`.
    All lists are ascending.
    """
    overdetermined_eqs: list[int]
    overdetermined_vars: list[int]
    underdetermined_eqs: list[int]
    underdetermined_vars: list[int]
    square_eqs: list[int]
    square_vars: list[int]
    unmatched_eqs: list[int]
    unmatched_vars: list[int]

    def overdetermined_subsystem(self) -> tuple[list[int], list[int]]:
        """(equations, variables): more equations than variables by len(unmatched_eqs)."""
        return sorted(self.overdetermined_eqs + self.unmatched_eqs), list(self.overdetermined_vars)

    def underdetermined_subsystem(self) -> tuple[list[int], list[int]]:
        """(equations, variables): more variables than equations by len(unmatched_vars)."""
        return list(self.underdetermined_eqs), sorted(self.underdetermined_vars + self.unmatched_vars)

    @property
    def is_square_and_nonsingular(self) -> bool:
        return not (self.unmatched_eqs or self.unmatched_vars)


def _variables_to_equations(n_vars: int, incidence: list[list[int]]) -> list[list[int]]:
    columns: list[list[int]] = [[] for _ in range(n_vars)]
    for eq, row in enumerate(incidence):
        for var in row:
            columns[var].append(eq)
    return columns


def dulmage_mendelsohn(n_eqs: int, n_vars: int, incidence: list[list[int]]) -> DMPartition:
    eq_to_var, var_to_eq = maximum_matching(n_eqs, n_vars, incidence)
    unmatched_eqs = [eq for eq in range(n_eqs) if eq_to_var[eq] == UNMATCHED]
    unmatched_vars = [var for var in range(n_vars) if var_to_eq[var] == UNMATCHED]

    over_eq = [False] * n_eqs
    over_var = [False] * n_vars
    pending = list(unmatched_eqs)
    for eq in pending:
        over_eq[eq] = True
    while pending:
        eq = pending.pop()
        for var in incidence[eq]:
            if over_var[var]:
                continue
            over_var[var] = True
            mate = var_to_eq[var]
            if mate != UNMATCHED and not over_eq[mate]:
                over_eq[mate] = True
                pending.append(mate)

    columns = _variables_to_equations(n_vars, incidence)
    under_eq = [False] * n_eqs
    under_var = [False] * n_vars
    pending = list(unmatched_vars)
    for var in pending:
        under_var[var] = True
    while pending:
        var = pending.pop()
        for eq in columns[var]:
            if under_eq[eq]:
                continue
            under_eq[eq] = True
            mate = eq_to_var[eq]
            if mate != UNMATCHED and not under_var[mate]:
                under_var[mate] = True
                pending.append(mate)

    unmatched_eq_set = [eq_to_var[eq] == UNMATCHED for eq in range(n_eqs)]
    unmatched_var_set = [var_to_eq[var] == UNMATCHED for var in range(n_vars)]
    return DMPartition(
        overdetermined_eqs=[eq for eq in range(n_eqs) if over_eq[eq] and not unmatched_eq_set[eq]],
        overdetermined_vars=[var for var in range(n_vars) if over_var[var]],
        underdetermined_eqs=[eq for eq in range(n_eqs) if under_eq[eq]],
        underdetermined_vars=[var for var in range(n_vars)
                              if under_var[var] and not unmatched_var_set[var]],
        square_eqs=[eq for eq in range(n_eqs) if not over_eq[eq] and not under_eq[eq]],
        square_vars=[var for var in range(n_vars) if not over_var[var] and not under_var[var]],
        unmatched_eqs=unmatched_eqs,
        unmatched_vars=unmatched_vars,
    )
