"""The initialization problem: the DAE's algebraic residuals plus the initial equations, in the
unknowns IDAS starts from (states x and algebraic z). Redundant consistent conditions are allowed
(the runtime solves in the least-squares sense and checks the residual). Too few conditions are
normal in Dyad code (a capacitor without `initial v = ...`): as Dyad's initialization does, the
unknowns left free are fixed at their start values / guesses (0 without either), preferring
states with a given value, then other states, then algebraic unknowns; InitialProblem.chosen
lists them for the note the commands print."""
from __future__ import annotations

import sympy

from compiler.errors import DyadError
from compiler.model.flat import FlatSystem, Origin
from compiler.model.symbols import free_symbols
from compiler.structure.graph.matching import augmenting_path, maximum_matching
from compiler.structure.reduced import Assignment, InitialProblem

_MAX_LISTED = 10


def build_initial_problem(flat: FlatSystem, alias, states: list[str], algebraics: list[str],
                          alg: list[sympy.Expr], alg_origins: list[Origin | None],
                          assignments: list[Assignment], observables: list[Assignment],
                          guesses: dict[str, float], seeds: dict[str, float] | None = None) -> InitialProblem:
    """The initialization problem (module doc). `guesses` are the declared start values and
    guesses (what a free unknown is fixed at); `seeds`, where given, the values the solve starts
    from (the guesses completed by the equations that give an unknown explicitly)."""
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
    chosen = _choose_free(flat, states, algebraics, assignments, residuals, guesses)
    for name, value in chosen.items():
        residuals.append(sympy.Symbol(name) - sympy.Float(value))
        origins.append(_declaration(flat, name))
    seeds = seeds if seeds is not None else guesses
    seeds = {n: seeds[n] for n in states + algebraics if n in seeds}
    return InitialProblem(residuals, origins, seeds, chosen)


def _substitute(expr: sympy.Expr, maps: list[dict]) -> sympy.Expr:
    for _ in range(1000):
        hit = {}
        for m in maps:
            hit.update({s: m[s] for s in expr.free_symbols if s in m})
        if not hit:
            return expr
        expr = expr.xreplace(hit)
    raise RuntimeError("substitution does not terminate")


# Beyond this many preferred candidates that do not raise the matching, the remaining free
# unknowns of the maximum matching are taken as they are (each failed try costs a graph search).
_MAX_FAILED_TRIES = 200


def _choose_free(flat: FlatSystem, states: list[str], algebraics: list[str],
                 assignments: list[Assignment], residuals: list[sympy.Expr],
                 guesses: dict[str, float]) -> dict[str, float]:
    """Unknowns to fix at their start values so that the initialization is structurally
    determined: {} when it already is. A maximum matching of the residuals is extended by one
    row `u = start(u)` per candidate u (in order of preference) that an augmenting path can
    match, until every unknown is matched."""
    unknowns = states + algebraics
    incidence = _incidence(unknowns, assignments, residuals)
    eq_to_var, var_to_eq = maximum_matching(len(residuals), len(unknowns), incidence)
    missing = sum(1 for e in var_to_eq if e < 0)
    if missing == 0:
        return {}
    state_set = set(states)
    order = sorted(range(len(unknowns)), key=lambda v: (unknowns[v] not in state_set,
                                                        unknowns[v] not in guesses, v))
    chosen: list[int] = []
    failed = 0
    for v in order:
        if len(chosen) == missing or failed > _MAX_FAILED_TRIES:
            break
        row = len(incidence)
        incidence.append([v])
        eq_to_var.append(-1)
        found, _, _ = augmenting_path(row, incidence, eq_to_var, var_to_eq)
        if found:
            chosen.append(v)
        else:
            incidence.pop()
            eq_to_var.pop()
            failed += 1
    chosen += [v for v, e in enumerate(var_to_eq) if e < 0]     # what the tries did not reach
    return {unknowns[v]: float(guesses.get(unknowns[v], 0.0)) for v in chosen}


def _incidence(unknowns: list[str], assignments: list[Assignment],
               residuals: list[sympy.Expr]) -> list[list[int]]:
    """Per residual, the unknowns it depends on (through the assignments it uses), sorted.
    Dependency sets are bit sets (Python ints): along a chain of assignments they grow with the
    model, and an OR of two ints is far cheaper than a union of two sets."""
    index = {sympy.Symbol(n): i for i, n in enumerate(unknowns)}
    depends: dict[sympy.Symbol, int] = {}

    def dependencies(expr: sympy.Expr) -> int:
        bits = 0
        for s in free_symbols(expr):
            if s in index:
                bits |= 1 << index[s]
            else:
                bits |= depends.get(s, 0)
        return bits

    for a in assignments:
        depends[sympy.Symbol(a.target)] = dependencies(a.expr)
    return [_set_bits(dependencies(r)) for r in residuals]


def _set_bits(bits: int) -> list[int]:
    """Positions of the 1 bits of `bits`, ascending."""
    digits = bin(bits)[:1:-1]                # least significant first, without the '0b'
    return [i for i, digit in enumerate(digits) if digit == "1"] if bits else []


def _declaration(flat: FlatSystem, name: str) -> Origin:
    """Where `name` is declared: the origin of the row that fixes it at its start value."""
    for variable in flat.variables:
        if variable.name == name:
            return variable.origin
    return Origin("")


def describe_chosen(chosen: dict[str, float]) -> str:
    """The note for an under-determined initialization, e.g. `capacitor.v = 0`."""
    listed = ", ".join(f"{n} = {v:g}" for n, v in list(chosen.items())[:_MAX_LISTED])
    more = f" and {len(chosen) - _MAX_LISTED} more" if len(chosen) > _MAX_LISTED else ""
    return (f"the initial conditions leave {len(chosen)} unknown(s) free; fixed at their start "
            f"values or guesses (0 where none is given), as Dyad's initialization does: "
            f"{listed}{more}")
