"""The structure stage: FlatSystem -> ReducedSystem, pass by pass, with a report of every pass."""
from __future__ import annotations

import time as _time
from dataclasses import dataclass, field

import numpy as np
import sympy

from compiler.errors import DyadError, Note
from compiler.model.flat import FlatSystem, Origin
from compiler.structure.alias import AliasResult, eliminate_aliases
from compiler.structure.causalize import Causalization, causalize
from compiler.structure.derivative_rank import RankReport, remove_derivative_dependencies
from compiler.structure.diagnostics import structural_singularity_error
from compiler.model.symbols import free_symbols
from compiler.structure.differentiate import partial
from compiler.structure.dummy_derivatives import DummySelection, select_dummy_derivatives, state_priority
from compiler.structure.index_reduction import IndexReductionReport, reduce_index
from compiler.structure.indexed import IndexedSystem, build_indexed
from compiler.structure.initialization import build_initial_problem
from compiler.structure.parameters import used_parameters
from compiler.structure.prune import prune_assignments
from compiler.structure.start_point import completed_point
from compiler.structure.reduced import Assignment, ReducedSystem


@dataclass
class StructureReport:
    """Everything `dyadc inspect` prints; kept beside the ReducedSystem, not inside the algorithms."""
    counts: dict[str, int] = field(default_factory=dict)
    timings: dict[str, float] = field(default_factory=dict)
    structural_index: int = 0
    states: list[str] = field(default_factory=list)
    dummy_derivatives: list[str] = field(default_factory=list)
    block_sizes: list[int] = field(default_factory=list)
    torn: list[str] = field(default_factory=list)
    pruned: list[str] = field(default_factory=list)
    pivot_conditions: list[float] = field(default_factory=list)
    levels: list[tuple[list[int], list[int], list[int]]] = field(default_factory=list)  # dummy selection


@dataclass
class Analysis:
    """Intermediate results a caller may re-use (e.g. to re-select states at another point)."""
    alias: AliasResult
    system: IndexedSystem
    index_report: IndexReductionReport
    priorities: dict[str, int]
    rank_report: RankReport | None = None


def analyse(flat: FlatSystem) -> Analysis:
    alias = eliminate_aliases(flat)
    residuals = [e.residual for e in alias.equations]
    parameter_values = {sympy.Symbol(p.name): p.value for p in flat.parameters if p.value is not None}
    residuals, rank_report = remove_derivative_dependencies(
        residuals, {sympy.Symbol(d) for d in alias.derivatives}, parameter_values)
    derivatives = _occurring_derivatives(alias.derivatives, residuals)
    system = build_indexed(alias.kept, derivatives, residuals, [e.origin for e in alias.equations])
    _check_square(flat, system)
    reduced_system, index_report = reduce_index(system)
    return Analysis(alias, reduced_system, index_report, _priorities(flat, alias), rank_report)


def _occurring_derivatives(derivatives: dict[str, str], residuals: list[sympy.Expr]) -> dict[str, str]:
    """Derivatives that some equation still contains (and the lower ones of their chains)."""
    occurring = {s.name for r in residuals for s in free_symbols(r)}
    keep = {d for d in derivatives if d in occurring}
    changed = True
    while changed:
        changed = False
        for d, base in derivatives.items():
            if d in keep and base in derivatives and base not in keep:
                keep.add(base)
                changed = True
    return {d: b for d, b in derivatives.items() if d in keep}


def reduce(flat: FlatSystem, point: dict[str, float] | None = None,
           report: StructureReport | None = None, analysis: Analysis | None = None,
           pivots=None) -> ReducedSystem:
    """`point` (values of unknowns and parameters) enables numeric pivoting of dummy derivatives;
    `pivots(rows, cols)`, given, replaces the Jacobian at `point` (to force one dummy choice)."""
    report = report if report is not None else StructureReport()
    if analysis is None:
        clock = _time.perf_counter()
        analysis = analyse(flat)
        report.timings["alias+rank+index"] = _time.perf_counter() - clock
    alias, system = analysis.alias, analysis.system
    report.counts.update({
        "flat variables": len(flat.variables), "flat equations": len(flat.equations),
        "after alias: variables": len(alias.kept), "after alias: equations": len(alias.equations),
        "derivative-dependent equations combined": len(analysis.rank_report.replaced) if analysis.rank_report else 0,
        "differentiated equations": analysis.index_report.differentiated,
        "index-1 equations": system.n_eqs, "index-1 unknowns": system.n_vars,
    })
    report.structural_index = analysis.index_report.structural_index

    clock = _time.perf_counter()
    selection = select_states(system, analysis.priorities, flat, point, pivots)
    report.timings["dummy derivatives"] = _time.perf_counter() - clock
    report.pivot_conditions = selection.pivot_conditions
    report.levels = selection.levels

    clock = _time.perf_counter()
    is_state = [False] * system.n_vars
    for v in selection.states:
        is_state[v] = True
    causal = causalize(system, is_state)
    if causal.unmatched_eqs or causal.unmatched_vars:
        raise structural_singularity_error(system, unknown_mask=[not s for s in is_state])
    report.timings["causalize"] = _time.perf_counter() - clock

    reduced = _assemble(flat, alias, system, selection, causal, report)
    reduced.statistics = {"counts": dict(report.counts), "structural_index": report.structural_index,
                          "states": list(report.states), "dummy_derivatives": list(report.dummy_derivatives)}
    return reduced


def select_states(system: IndexedSystem, priorities: dict[str, int], flat: FlatSystem,
                  point: dict[str, float] | None, pivots=None) -> DummySelection:
    priority = state_priority(system, priorities)
    if pivots is not None or point is None:
        selection = select_dummy_derivatives(system, priority, pivots)
    else:
        selection = select_dummy_derivatives(system, priority, _numeric_jacobian(system, flat, point, True))
        if selection.deficient or not selection.numeric:
            # singular, or not finite (1/sqrt(0)), where unknowns without values are 0: again with
            # those the equations give explicitly (time-driven positions, auxiliaries) computed first
            completed = completed_point(system, flat, point)
            retried = select_dummy_derivatives(system, priority, _numeric_jacobian(system, flat, completed, True))
            if not retried.deficient and (selection.deficient or retried.numeric):
                selection = retried
        if selection.deficient:     # still singular: the structural choice, as before
            selection = select_dummy_derivatives(system, priority, _numeric_jacobian(system, flat, point, False))
    if selection.deficient:
        rows = [e for level in selection.levels for e in level[0]]
        raise DyadError("index reduction failed: the differentiated constraints do not determine "
                        "enough derivatives (the mechanism is singular or over-constrained here)",
                        next((system.origins[e].span for e in rows if system.origins[e]), None),
                        notes=[Note(str(system.equations[e]), system.origins[e].span if system.origins[e] else None)
                               for e in rows[:6]])
    return selection


def _numeric_jacobian(system: IndexedSystem, flat: FlatSystem, point: dict[str, float], fill: bool):
    """The level Jacobians at `point`. With `fill`, an unknown without a value (no guess, no
    start) is 0, the value the initialization starts it from; without, a level that needs one
    falls back to the structural choice, which breaks ties between candidates by their names (a
    renamed variable changed the state set: the metamorphic tests' PendulumA01, issue 25)."""
    values = {symbol: 0.0 for symbol in system.symbols} if fill else {}
    values.update({sympy.Symbol(k): v for k, v in point.items()})
    values.update({sympy.Symbol(p.name): p.value for p in flat.parameters if p.value is not None})
    substitute = _shared_xreplace(values)

    def jacobian(rows: list[int], cols: list[int]) -> np.ndarray:
        out = np.zeros((len(rows), len(cols)))
        col_index = {v: j for j, v in enumerate(cols)}
        for i, e in enumerate(rows):
            for v in system.incidence[e]:
                j = col_index.get(v)
                if j is None:
                    continue
                coefficient = partial(system.equations[e], system.symbols[v])
                try:
                    out[i, j] = float(substitute(coefficient))
                except (TypeError, ValueError):
                    return None      # the point does not cover these unknowns: fall back to structure
        if np.isnan(out).any():
            return None
        return out

    return jacobian


def _shared_xreplace(rule: dict):
    """`expr.xreplace(rule)` (the same rebuild, node by node), remembering every subtree's result:
    the coefficients of one equation share most of their subtrees (sin(phi) * r, ...), and
    evaluating them in floats through sympy is the costly part of the numeric Jacobian."""
    done: dict[sympy.Basic, tuple[object, bool]] = {}

    def replace(expr) -> tuple[object, bool]:
        found = done.get(expr)
        if found is None:
            if expr in rule:
                found = (rule[expr], True)
            else:
                args, changed = [], False
                for arg in expr.args:
                    new, arg_changed = replace(arg) if isinstance(arg, sympy.Basic) else (arg, False)
                    args.append(new)
                    changed |= arg_changed
                found = (expr.func(*args), True) if changed else (expr, False)
            done[expr] = found
        return found

    return lambda expr: replace(expr)[0]


def _priorities(flat: FlatSystem, alias: AliasResult) -> dict[str, int]:
    priorities = {v.name: v.state_priority for v in flat.variables}
    for name, expr in alias.eliminated.items():
        kept = [s.name for s in free_symbols(expr) if s.name in priorities]
        if len(kept) == 1 and priorities[name] > priorities[kept[0]]:
            priorities[kept[0]] = priorities[name]
    return priorities


def _check_square(flat: FlatSystem, system: IndexedSystem) -> None:
    diff_to_var = system.diff_to_var()
    chains = sum(1 for v in range(system.n_vars) if diff_to_var[v] < 0)
    if chains != system.n_eqs:
        raise structural_singularity_error(system)


def _assemble(flat, alias, system, selection, causal: Causalization, report) -> ReducedSystem:
    names = system.names
    states = [names[v] for v in selection.states]
    ode = [system.symbols[system.var_to_diff[v]] for v in selection.states]
    algebraics = [names[v] for v in causal.torn]
    alg = [system.equations[e] for e in causal.residual_equations]
    assignments = [Assignment(names[v], expr, system.origins[e]) for e, v, expr in causal.assignments]
    kept, pruned = prune_assignments(assignments, ode + alg)
    alias_observables = [Assignment(name, expr, None) for name, expr in alias.eliminated.items()]
    observables = pruned + alias_observables

    report.states = states
    report.dummy_derivatives = [names[v] for v in selection.dummies]
    report.block_sizes = causal.block_sizes
    report.torn = algebraics
    report.pruned = [a.target for a in pruned]
    report.counts.update({"states": len(states), "algebraic (IDAS)": len(algebraics),
                          "assignments": len(kept), "observables": len(observables)})

    guesses = flat.initial_values()
    # The initialization starts an unknown without a value where an equation puts it given the
    # others' values (`a = y^2` under `L = sqrt(x^2 + a)` at 0 made L 0 and `d / L` nan).
    seeds = completed_point(system, flat, guesses)
    initial = build_initial_problem(flat, alias, states, algebraics, alg,
                                    [system.origins[e] for e in causal.residual_equations],
                                    kept, observables, guesses, seeds)
    # Every parameter of the index-1 equations, also one that cancels from all of the above
    # (`s * x = s * y` solved as x = y): the state-set monitor's pivots are derivatives of these
    # equations and may hold it (a Body's equations scaled by a parameter, issue 25).
    expressions = ode + alg + [a.expr for a in kept] + [a.expr for a in observables] + initial.residuals \
        + list(system.equations)
    parameters = used_parameters(flat, expressions)
    return ReducedSystem(
        name=flat.name, states=states, ode=ode, algebraics=algebraics, alg=alg,
        assignments=kept, observables=observables, parameters=parameters, initial=initial,
        output_names=[v.name for v in flat.variables],
        alg_origins=[system.origins[e] for e in causal.residual_equations],
        metadata=dict(flat.metadata, nominals=_nominals(flat, states + algebraics),
                      units={q.name: q.units for q in [*flat.variables, *flat.parameters] if q.units}),
    )


def _nominals(flat: FlatSystem, names: list[str]) -> dict[str, float]:
    """Size of each IDAS unknown, from its start value: absolute tolerances scale with it
    (a pressure of 1e7 Pa and an angle of 1 rad cannot share one absolute tolerance)."""
    starts = {v.name: v.start for v in flat.variables if v.start is not None}
    return {n: max(1.0, abs(float(starts[n]))) for n in names if n in starts and abs(float(starts[n])) > 1.0}
