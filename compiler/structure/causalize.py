"""From the index-1 system to assignments and residuals: matching, BLT, solve-for, tearing.

Given the states (known to the algebraic problem), every other unknown is matched to an equation;
the BLT blocks are solved in order: a scalar block linear in its unknown becomes an explicit
assignment, every other block is torn: its torn unknowns go to IDAS as algebraic variables with
the block's residual equations, the rest of the block becomes assignments.
Large systems whose torn form would be dense keep chains of assignments as IDAS unknowns (_sparse_form).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy

from compiler.model.flat import TIME
from compiler.model.symbols import free_symbols
from compiler.structure.differentiate import partial
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
        """Solvable with a coefficient of parameters and constants only: the division can never
        be by zero along the run. A coefficient that varies, with the unknowns or with time (a
        road height r * sin(omega * time) as a lever arm), can pass zero where the block is regular."""
        coefficient = self._coefficient(e, v)
        if coefficient is None:
            return False
        return not any(s in self.system.index_of or s == TIME for s in free_symbols(coefficient))

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
        # y = x + ifelse(y > 0.5, 1, 0): the condition's derivative is 0, but solving by putting
        # y = 0 in the rest would read the condition at y = 0 (it gave y = x)
        conditions = [pair.cond for piecewise in self.system.equations[e].atoms(sympy.Piecewise)
                      for pair in piecewise.args]
        if any(sym in free_symbols(condition) for condition in conditions):
            return None
        return coefficient


# The sparse form (see _sparse_form) is considered from this many IDAS unknowns (states + torn)
# on, when the torn system's Jacobian has at least this structural density: below, today's torn
# form is kept (every small model, every golden trajectory, bit for bit). Measured on the N-link
# chain (docs/scaling.md, whole simulate): torn faster up to N = 32 (96 unknowns: 0.066 s vs
# 0.118 s), sparse from N = 64 (192 unknowns: 0.205 s vs 0.536 s).
SPARSE_FORM_FROM = 150
DENSE_FROM = 0.1
# An assignment whose value depends (through earlier assignments) on more IDAS unknowns than this
# becomes an IDAS unknown itself in the sparse form.
FAN_IN_LIMIT = 8


@dataclass
class _BlockPlan:
    """One BLT block: tear variables, residual equations, causal (equation, unknown) pairs."""
    tear_vars: list[int]
    residual_eqs: list[int]
    causal: list[tuple[int, int]]


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
    plans: list[_BlockPlan] = []
    for eqs, local_vars in blocks:
        block_vars = [unknowns[i] for i in local_vars]
        if len(eqs) == 1 and solver.solvable(eqs[0], block_vars[0]):
            plans.append(_BlockPlan([], [], [(eqs[0], block_vars[0])]))
            continue
        # Inside a loop, a pair whose coefficient depends on unknowns (a lever arm that passes zero)
        # would divide by zero where the loop itself is regular: those unknowns are torn instead.
        tearing = tear_block(list(eqs), list(local_vars), incidence,
                             lambda e, lv: solver.safely_solvable(e, unknowns[lv]))
        plans.append(_BlockPlan([unknowns[lv] for lv in tearing.tear_vars], list(tearing.residual_eqs),
                                [(e, unknowns[lv]) for e, lv in tearing.causal]))
    freed = _sparse_form(system, is_known, plans)
    result = Causalization([], [], [], block_sizes=[len(eqs) for eqs, _ in blocks])
    for plan in plans:
        result.torn.extend(plan.tear_vars)
        result.residual_equations.extend(plan.residual_eqs)
        for e, v in plan.causal:
            if (e, v) in freed:
                result.torn.append(v)
                result.residual_equations.append(e)
            else:
                result.assignments.append((e, v, solver.solution(e, v)))
    return result


def _sparse_form(system: IndexedSystem, is_known: list[bool], plans: list[_BlockPlan]) -> set:
    """The causal pairs to hand to IDAS as unknown + residual instead of assigning them.

    Tearing substitutes assignments into the residuals; where they chain (a link's orientation is
    the sum of all joint angles before it, a joint's force the sum of all accelerations after it),
    every residual depends on every IDAS unknown: the chain's iteration matrix is a third full
    and its factorization O(n^3). Cutting every chain where an assignment's fan-in exceeds
    FAN_IN_LIMIT keeps the Jacobian at O(n) entries (more, but local, unknowns), which a sparse
    LU factorizes in O(n). Chosen only for large systems that would be dense (measured here, at
    compile time, on the structure) and when the estimated factorization work is smaller."""
    torn_size, torn_nnz, _ = _jacobian_structure(system, is_known, plans, None)
    if torn_size < SPARSE_FORM_FROM or torn_nnz < DENSE_FROM * torn_size ** 2:
        return set()
    sparse_size, sparse_nnz, freed = _jacobian_structure(system, is_known, plans, FAN_IN_LIMIT)
    # LU work: dense ~ n^3/3; a sparse matrix with local coupling ~ (entries per column)^2 per column.
    if not freed or sparse_nnz ** 2 / sparse_size >= torn_size ** 3 / 3:
        return set()
    return freed


def _jacobian_structure(system: IndexedSystem, is_known: list[bool], plans: list[_BlockPlan],
                        fan_in_limit: int | None) -> tuple[int, int, set]:
    """(IDAS unknowns, structural nonzeros of the IDAS Jacobian, freed pairs) when every causal
    pair whose fan-in exceeds `fan_in_limit` (None: never) becomes an IDAS unknown. A value's
    dependencies on the IDAS unknowns are kept as bit sets (Python ints)."""
    depends: dict[int, int] = {}
    columns = 0

    def new_column(v: int) -> None:
        nonlocal columns
        depends[v] = 1 << columns
        columns += 1

    def row(e: int, skip: int = -1) -> int:
        bits = 0
        for u in system.incidence[e]:
            if u != skip:
                bits |= depends[u]
        return bits

    states = [v for v in range(system.n_vars) if is_known[v]]
    for v in states:
        new_column(v)
    freed: set[tuple[int, int]] = set()
    residuals: list[int] = []
    for plan in plans:
        for v in plan.tear_vars:
            new_column(v)
        residuals.extend(plan.residual_eqs)
        for e, v in plan.causal:
            bits = row(e, skip=v)
            if fan_in_limit is not None and bits.bit_count() > fan_in_limit:
                freed.add((e, v))
                residuals.append(e)
                new_column(v)
            else:
                depends[v] = bits
    nnz = sum(depends[system.var_to_diff[v]].bit_count() for v in states)
    nnz += sum(row(e).bit_count() for e in residuals)
    return columns, nnz, freed
