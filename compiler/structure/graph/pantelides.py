"""Structural index reduction (Pantelides 1988), on integer structures.

The formulation follows ModelingToolkit / StateSelection.jl: derivative variables are ordinary
columns of the incidence, linked by `var_to_diff[v]` = index of der(v) (or -1). Only
highest-derivative variables (those with `var_to_diff[v] == -1`) take part in the matching.
When an equation cannot be matched, every equation visited by the failed augmenting path is
differentiated and every visited variable gets a derivative; the derivatives inherit the matching
(der(v) is matched to the derivative of the equation v was matched to), and the search resumes
from the derivative of the equation that failed.

The structural incidence of the derivative of an equation is, for each variable v of the
original, {v, der(v)}: a conservative superset (the symbolic layer computes the real expression).
"""
from __future__ import annotations

from dataclasses import dataclass, field

from compiler.structure.graph.matching import UNMATCHED, augmenting_path, maximum_matching


class StructurallySingular(Exception):
    """No (finite) number of differentiations makes the equations matchable.

    `unmatched_eqs` are equations left without a variable by a maximum matching in which every
    variable and all of its derivatives count as one unknown (Pryce's criterion for the
    termination of Pantelides' algorithm), or the equation whose search hit `max_rounds`.
    """

    def __init__(self, unmatched_eqs: list[int], message: str | None = None):
        self.unmatched_eqs = list(unmatched_eqs)
        super().__init__(message or f"structurally singular: equations {self.unmatched_eqs} "
                                    "cannot be matched to distinct unknowns")


@dataclass
class PantelidesResult:
    """The index-reduced structure. Indices below n_eqs/n_vars of the input are unchanged.

    eq_to_var / var_to_eq: a matching of every non-empty highest-derivative equation
    (`eq_to_diff[eq] == -1`) to a highest-derivative variable; -1 for differentiated equations,
    empty equations and non-highest variables.
    differentiation_order: (differentiated_eq, its_derivative_eq) in creation order; the
    differentiated equation may itself be a derivative equation created earlier.
    """
    incidence: list[list[int]]
    var_to_diff: list[int]
    eq_to_diff: list[int]
    n_eqs: int
    n_vars: int
    eq_to_var: list[int]
    differentiation_order: list[tuple[int, int]]
    var_to_eq: list[int] = field(default_factory=list)

    def differentiation_counts(self) -> list[int]:
        """How many times each equation's chain continues: counts[eq] = length of its eq_to_diff chain."""
        counts = [0] * self.n_eqs
        # Derivative equations always get larger indices than their source, so a reverse sweep
        # sees each derivative before the equation it came from.
        for eq in range(self.n_eqs - 1, -1, -1):
            derivative = self.eq_to_diff[eq]
            if derivative != UNMATCHED:
                counts[eq] = counts[derivative] + 1
        return counts


def invert_derivative_chain(to_diff: list[int]) -> list[int]:
    """from_diff[d] = the index whose derivative is d, or -1 (for var_to_diff or eq_to_diff)."""
    from_diff = [UNMATCHED] * len(to_diff)
    for index, derivative in enumerate(to_diff):
        if derivative != UNMATCHED:
            from_diff[derivative] = index
    return from_diff


def derivative_families(var_to_diff: list[int]) -> list[int]:
    """family[v] = the undifferentiated root of v's derivative chain (x, der(x), der(der(x)) share one)."""
    from_diff = invert_derivative_chain(var_to_diff)
    family = [UNMATCHED] * len(var_to_diff)
    for root in range(len(var_to_diff)):
        if from_diff[root] != UNMATCHED:
            continue
        var = root
        while var != UNMATCHED and family[var] == UNMATCHED:
            family[var] = root
            var = var_to_diff[var]
    for var in range(len(var_to_diff)):
        if family[var] == UNMATCHED:
            raise ValueError(f"var_to_diff contains a cycle through variable {var}")
    return family


def _check_matchable_up_to_differentiation(n_eqs: int, n_vars: int, incidence: list[list[int]],
                                           var_to_diff: list[int]) -> None:
    family = derivative_families(var_to_diff)
    family_incidence = [sorted({family[var] for var in incidence[eq]}) for eq in range(n_eqs)]
    eq_to_family, _ = maximum_matching(n_eqs, n_vars, family_incidence)
    unmatched = [eq for eq in range(n_eqs) if incidence[eq] and eq_to_family[eq] == UNMATCHED]
    if unmatched:
        raise StructurallySingular(unmatched)


class _GrowingStructure:
    """The incidence, derivative links and matching while Pantelides adds equations and variables."""

    def __init__(self, n_eqs: int, n_vars: int, incidence: list[list[int]], var_to_diff: list[int]):
        self.incidence = [list(row) for row in incidence]
        self.var_to_diff = list(var_to_diff)
        self.eq_to_diff = [UNMATCHED] * n_eqs
        self.is_highest = [derivative == UNMATCHED for derivative in self.var_to_diff]
        self.eq_to_var = [UNMATCHED] * n_eqs
        self.var_to_eq = [UNMATCHED] * n_vars
        self.differentiation_order: list[tuple[int, int]] = []

    def differentiate_variable(self, var: int) -> int:
        derivative = len(self.var_to_diff)
        self.var_to_diff.append(UNMATCHED)
        self.is_highest.append(True)
        self.var_to_eq.append(UNMATCHED)
        self.var_to_diff[var] = derivative
        self.is_highest[var] = False
        return derivative

    def differentiate_equation(self, eq: int) -> int:
        new_row: set[int] = set()
        for var in self.incidence[eq]:
            if self.var_to_diff[var] == UNMATCHED:
                self.differentiate_variable(var)
            new_row.add(var)
            new_row.add(self.var_to_diff[var])
        derivative = len(self.incidence)
        self.incidence.append(sorted(new_row))
        self.eq_to_diff.append(UNMATCHED)
        self.eq_to_var.append(UNMATCHED)
        self.eq_to_diff[eq] = derivative
        self.differentiation_order.append((eq, derivative))
        return derivative


def pantelides(n_eqs: int, n_vars: int, incidence: list[list[int]], var_to_diff: list[int], *,
               max_rounds: int = 10) -> PantelidesResult:
    """Differentiate equations until all of them match distinct highest-derivative variables.

    Equations with an empty incidence are skipped (left unmatched) for the symbolic layer to
    judge. `max_rounds` bounds how many times the search for one original equation may
    differentiate (that is, a bound on the index); exceeding it raises StructurallySingular.
    Raises StructurallySingular up front when no number of differentiations can help.
    """
    if len(incidence) != n_eqs or len(var_to_diff) != n_vars:
        raise ValueError("incidence / var_to_diff lengths disagree with n_eqs / n_vars")
    _check_matchable_up_to_differentiation(n_eqs, n_vars, incidence, var_to_diff)
    state = _GrowingStructure(n_eqs, n_vars, incidence, var_to_diff)
    # A maximum matching first: equations it matches never need differentiating on their own,
    # which keeps the per-equation searches below to the few equations that really fail.
    state.eq_to_var, state.var_to_eq = maximum_matching(
        n_eqs, n_vars, state.incidence, var_allowed=state.is_highest)

    for original in range(n_eqs):
        if not state.incidence[original] or state.eq_to_var[original] != UNMATCHED:
            continue
        current = original
        for _ in range(max_rounds + 1):
            found, visited_eqs, visited_vars = augmenting_path(
                current, state.incidence, state.eq_to_var, state.var_to_eq, state.is_highest)
            if found:
                break
            for var in sorted(visited_vars):
                state.differentiate_variable(var)
            for eq in sorted(visited_eqs):
                state.differentiate_equation(eq)
            for var in visited_vars:
                derivative_var = state.var_to_diff[var]
                derivative_eq = state.eq_to_diff[state.var_to_eq[var]]
                state.var_to_eq[derivative_var] = derivative_eq
                state.eq_to_var[derivative_eq] = derivative_var
            current = state.eq_to_diff[current]
        else:
            raise StructurallySingular(
                [original], f"equation {original} still unmatched after {max_rounds} "
                            "differentiations (max_rounds)")

    total_eqs = len(state.incidence)
    total_vars = len(state.var_to_diff)
    eq_to_var = [state.eq_to_var[eq] if state.eq_to_diff[eq] == UNMATCHED else UNMATCHED
                 for eq in range(total_eqs)]
    var_to_eq = [UNMATCHED] * total_vars
    for eq, var in enumerate(eq_to_var):
        if var != UNMATCHED:
            var_to_eq[var] = eq
    return PantelidesResult(
        incidence=state.incidence, var_to_diff=state.var_to_diff, eq_to_diff=state.eq_to_diff,
        n_eqs=total_eqs, n_vars=total_vars, eq_to_var=eq_to_var,
        differentiation_order=state.differentiation_order, var_to_eq=var_to_eq)


def structural_index(result: PantelidesResult) -> int:
    """The differentiation index implied by the Pantelides result.

    index = (max number of times one equation was differentiated) + 1 if some matched unknown of
    the final system stays purely algebraic (neither a derivative nor differentiated), else + 0:
    the last differentiation then already yields an ODE for every unknown. The Cartesian pendulum
    is 3 (the rod tension stays algebraic); a circuit whose hidden constraint, differentiated once,
    gives every voltage a derivative is 1 (the Test Set's transistor amplifier); an explicit ODE 0.
    """
    counts = result.differentiation_counts()
    deepest = max(counts, default=0)
    is_derivative = [False] * result.n_vars
    for derivative in result.var_to_diff:
        if derivative != UNMATCHED:
            is_derivative[derivative] = True
    algebraic_left = any(var != UNMATCHED and not is_derivative[var] and result.var_to_diff[var] == UNMATCHED
                         for var in result.eq_to_var)
    return deepest + (1 if algebraic_left else 0)
