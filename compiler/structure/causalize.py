"""From the index-1 system to assignments and residuals: matching, BLT, solve-for, tearing.

Given the states (known to the algebraic problem), every other unknown is matched to an equation;
the BLT blocks are solved in order: a scalar block linear in its unknown becomes an explicit
assignment, every other block is torn: its torn unknowns go to IDAS as algebraic variables with
the block's residual equations, the rest of the block becomes assignments.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy

from compiler.structure.differentiate import free_symbols, partial
from compiler.structure.graph.blt import block_lower_triangular
from compiler.structure.graph.matching import maximum_matching
from compiler.structure.graph.tearing import tear_block
from compiler.structure.indexed import IndexedSystem


@dataclass
class Causalization:
    assignments: list[tuple[int, int, sympy.Expr]]    # (equation, unknown, expression) in order
    torn: list[int]                                    # unknowns solved by IDAS (algebraic z)
    residual_equations: list[int]                      # their residual equations
    block_sizes: list[int] = field(default_factory=list)
    unmatched_eqs: list[int] = field(default_factory=list)
    unmatched_vars: list[int] = field(default_factory=list)


class LinearSolver:
    """Answers 'can equation e be solved explicitly for unknown v' and caches the answer; the
    solution itself is built only for the pairs that become assignments."""

    def __init__(self, system: IndexedSystem):
        self.system = system
        self._coefficients: dict[tuple[int, int], sympy.Expr | None] = {}

    def solution(self, e: int, v: int) -> sympy.Expr | None:
        coefficient = self._coefficient(e, v)
        if coefficient is None:
            return None
        rest = self.system.equations[e].xreplace({self.system.symbols[v]: sympy.Integer(0)})
        return -rest / coefficient

    def solvable(self, e: int, v: int) -> bool:
        return self._coefficient(e, v) is not None

    def safely_solvable(self, e: int, v: int) -> bool:
        """Solvable with a coefficient free of unknowns: the division can never be by zero."""
        coefficient = self._coefficient(e, v)
        if coefficient is None:
            return False
        return not any(s in self.system.index_of for s in free_symbols(coefficient))

    def _coefficient(self, e: int, v: int) -> sympy.Expr | None:
        """d residual / d unknown if the residual is linear in the unknown (and the coefficient
        is no switch that could be zero on one side); else None."""
        key = (e, v)
        if key not in self._coefficients:
            self._coefficients[key] = self._linear_coefficient(e, v)
        return self._coefficients[key]

    def _linear_coefficient(self, e: int, v: int) -> sympy.Expr | None:
        sym = self.system.symbols[v]
        coefficient = partial(self.system.equations[e], sym)
        if coefficient == 0 or sym in free_symbols(coefficient):
            return None
        if coefficient.has(sympy.Piecewise, sympy.Heaviside, sympy.DiracDelta):
            return None
        return coefficient


def causalize(system: IndexedSystem, is_known: list[bool]) -> Causalization:
    unknowns = [v for v in range(system.n_vars) if not is_known[v]]
    local = {v: i for i, v in enumerate(unknowns)}
    incidence = [[local[v] for v in row if v in local] for row in system.incidence]
    eq_to_local, local_to_eq = maximum_matching(system.n_eqs, len(unknowns), incidence)
    unmatched_eqs = [e for e, m in enumerate(eq_to_local) if m < 0]
    unmatched_vars = [unknowns[i] for i, m in enumerate(local_to_eq) if m < 0]
    if unmatched_eqs or unmatched_vars:
        return Causalization([], [], [], unmatched_eqs=unmatched_eqs, unmatched_vars=unmatched_vars)
    blocks = block_lower_triangular(system.n_eqs, incidence, eq_to_local)
    solver = LinearSolver(system)
    result = Causalization([], [], [])
    for eqs, local_vars in blocks:
        block_vars = [unknowns[i] for i in local_vars]
        result.block_sizes.append(len(eqs))
        if len(eqs) == 1 and solver.solvable(eqs[0], block_vars[0]):
            result.assignments.append((eqs[0], block_vars[0], solver.solution(eqs[0], block_vars[0])))
            continue
        # Inside a loop, a pair whose coefficient depends on unknowns (a lever arm that passes zero)
        # would divide by zero where the loop itself is regular: those unknowns are torn instead.
        tearing = tear_block(list(eqs), list(local_vars), incidence,
                             lambda e, lv: solver.safely_solvable(e, unknowns[lv]))
        for e, lv in tearing.causal:
            v = unknowns[lv]
            result.assignments.append((e, v, solver.solution(e, v)))
        result.torn.extend(unknowns[lv] for lv in tearing.tear_vars)
        result.residual_equations.extend(tearing.residual_eqs)
    return result
