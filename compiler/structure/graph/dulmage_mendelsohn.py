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


def _alternating_reach(starts: list[int], neighbours: list[list[int]], mate: list[int],
                       n_side: int, n_other: int) -> tuple[list[bool], list[bool]]:
    """Nodes reachable from unmatched `starts` by alternating paths (any edge out, matched edge
    back): from unmatched equations this is the over-determined part, from unmatched variables
    (with the transposed incidence) the under-determined part."""
    side = [False] * n_side
    other = [False] * n_other
    pending = list(starts)
    for node in pending:
        side[node] = True
    while pending:
        node = pending.pop()
        for neighbour in neighbours[node]:
            if other[neighbour]:
                continue
            other[neighbour] = True
            partner = mate[neighbour]
            if partner != UNMATCHED and not side[partner]:
                side[partner] = True
                pending.append(partner)
    return side, other


def dulmage_mendelsohn(n_eqs: int, n_vars: int, incidence: list[list[int]]) -> DMPartition:
    eq_to_var, var_to_eq = maximum_matching(n_eqs, n_vars, incidence)
    unmatched_eqs = [eq for eq in range(n_eqs) if eq_to_var[eq] == UNMATCHED]
    unmatched_vars = [var for var in range(n_vars) if var_to_eq[var] == UNMATCHED]

    over_eq, over_var = _alternating_reach(unmatched_eqs, incidence, var_to_eq, n_eqs, n_vars)
    columns = _variables_to_equations(n_vars, incidence)
    under_var, under_eq = _alternating_reach(unmatched_vars, columns, eq_to_var, n_vars, n_eqs)

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
