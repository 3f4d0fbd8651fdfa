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
    """over-, under- and square- groups partition the equations, and likewise the variables.

    The unmatched equations (a maximum matching leaves them without a variable) are included in
    `overdetermined_eqs`, the unmatched variables in `underdetermined_vars`; `unmatched_eqs` /
    `unmatched_vars` list them again (which ones are unmatched depends on the matching found;
    the three groups do not). All lists are ascending. Counts:
    len(overdetermined_eqs) = len(overdetermined_vars) + len(unmatched_eqs), and
    len(underdetermined_vars) = len(underdetermined_eqs) + len(unmatched_vars).
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
        return list(self.overdetermined_eqs), list(self.overdetermined_vars)

    def underdetermined_subsystem(self) -> tuple[list[int], list[int]]:
        return list(self.underdetermined_eqs), list(self.underdetermined_vars)

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

    return DMPartition(
        overdetermined_eqs=[eq for eq in range(n_eqs) if over_eq[eq]],
        overdetermined_vars=[var for var in range(n_vars) if over_var[var]],
        underdetermined_eqs=[eq for eq in range(n_eqs) if under_eq[eq]],
        underdetermined_vars=[var for var in range(n_vars) if under_var[var]],
        square_eqs=[eq for eq in range(n_eqs) if not over_eq[eq] and not under_eq[eq]],
        square_vars=[var for var in range(n_vars) if not over_var[var] and not under_var[var]],
        unmatched_eqs=unmatched_eqs,
        unmatched_vars=unmatched_vars,
    )
