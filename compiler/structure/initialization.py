"""The initialization problem: the DAE's algebraic residuals plus the initial equations, in the
unknowns IDAS starts from (states x and algebraic z). Redundant consistent conditions are allowed
(the runtime solves in the least-squares sense and checks the residual); too few conditions are
an error here, naming the states nobody fixes."""
from __future__ import annotations

import sympy

from compiler.errors import DyadError, Note
from compiler.model.flat import FlatSystem, Origin
from compiler.structure.graph.matching import maximum_matching
from compiler.structure.reduced import Assignment, InitialProblem

_MAX_LISTED = 10


def build_initial_problem(flat: FlatSystem, alias, states: list[str], algebraics: list[str],
                          alg: list[sympy.Expr], alg_origins: list[Origin | None],
                          assignments: list[Assignment], observables: list[Assignment],
                          guesses: dict[str, float]) -> InitialProblem:
    observable_map = {sympy.Symbol(a.target): a.expr for a in observables}
    alias_map = {sympy.Symbol(k): v for k, v in alias.eliminated.items()}
    known = ({sympy.Symbol(n) for n in states} | {sympy.Symbol(n) for n in algebraics}
             | {sympy.Symbol(a.target) for a in assignments})
    parameters = {sympy.Symbol(p.name) for p in flat.parameters}
    from compiler.model.flat import TIME

    residuals = list(alg)
    origins = list(alg_origins)
    for eq in flat.initial_equations:
        expr = _substitute(eq.residual, [alias_map, alias.derivative_mapping, observable_map])
        unknown = sorted(s.name for s in expr.free_symbols if s not in known and s not in parameters and s != TIME)
        if unknown:
            raise DyadError(f"initial equation refers to `{unknown[0]}`, which the reduced model does not "
                            "compute at the start time", eq.origin.span,
                            hint="initial conditions may use variables and der() of states")
        residuals.append(expr)
        origins.append(eq.origin)
    _check_determined(states, algebraics, assignments, residuals, origins)
    seeds = {n: guesses[n] for n in states + algebraics if n in guesses}
    return InitialProblem(residuals, origins, seeds)


def _substitute(expr: sympy.Expr, maps: list[dict]) -> sympy.Expr:
    for _ in range(1000):
        hit = {}
        for m in maps:
            hit.update({s: m[s] for s in expr.free_symbols if s in m})
        if not hit:
            return expr
        expr = expr.xreplace(hit)
    raise RuntimeError("substitution does not terminate")


def _check_determined(states, algebraics, assignments, residuals, origins) -> None:
    unknowns = states + algebraics
    index = {sympy.Symbol(n): i for i, n in enumerate(unknowns)}
    depends: dict[sympy.Symbol, frozenset[int]] = {}
    for a in assignments:
        deps: set[int] = set()
        for s in a.expr.free_symbols:
            if s in index:
                deps.add(index[s])
            elif s in depends:
                deps |= depends[s]
        depends[sympy.Symbol(a.target)] = frozenset(deps)
    incidence = []
    for r in residuals:
        deps = set()
        for s in r.free_symbols:
            if s in index:
                deps.add(index[s])
            elif s in depends:
                deps |= depends[s]
        incidence.append(sorted(deps))
    _, var_to_eq = maximum_matching(len(residuals), len(unknowns), incidence)
    free = [unknowns[i] for i, e in enumerate(var_to_eq) if e < 0]
    if free:
        listed = ", ".join(free[:_MAX_LISTED]) + (f" and {len(free) - _MAX_LISTED} more" if len(free) > _MAX_LISTED else "")
        raise DyadError(f"the initial conditions are under-determined: nothing fixes {listed} at the start time",
                        None, hint="add `initial` equations or `(initial = ...)` modifiers for these "
                        f"states ({len(states)} states need {len(states)} independent initial conditions)")
