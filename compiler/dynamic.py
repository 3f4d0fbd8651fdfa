"""Dynamic state selection: integrate in segments, switch the state set where the current one
degrades, continue from a consistent point, join the segments into one result.

A variant is the model compiled for one choice of dummy derivatives. Besides the user's signals
it outputs every unknown of the index-1 system (so that any other variant can start from its
values) and, for each level of the dummy-derivative choice whose pivot block depends on the
unknowns, the entries of that level's Jacobian. After each output point the pivot choice is redone
on those numbers; when a different choice is clearly better (the current block's smallest
singular value below SWITCH_RATIO times the alternative's), the state set is switched there.
A choice whose pivot blocks are constant is valid everywhere: it is never monitored.
"""
from __future__ import annotations

import copy
import math
import time as _time
from dataclasses import dataclass, field

import casadi as ca
import numpy as np
import sympy

from compiler import runtime
from compiler.flat import FlatSystem
from compiler.lower_casadi import lower
from compiler.structure.dummy_derivatives import base_variable
from compiler.structure.reduce import Analysis, StructureReport, reduce, select_states
from compiler.structure.reduced import Assignment, ReducedSystem

SWITCH_RATIO = runtime.STATE_SWITCH_RATIO
SEGMENT_POINTS = 50


@dataclass
class Variant:
    states: tuple[str, ...]
    reduced: ReducedSystem
    model: runtime.CompiledModel
    report: StructureReport
    public_names: list[str]
    # every state set reached from this one, built once and kept for later runs (shared by all)
    siblings: dict = field(default_factory=dict)


def monitored_levels(flat: FlatSystem, analysis: Analysis, report: StructureReport) -> list[tuple]:
    """Levels of the dummy-derivative choice that can degrade: more candidates than rows and a
    chosen pivot block that depends on the unknowns. Each as (level, rows, candidates, chosen)."""
    system = analysis.system
    constant = set(sympy.Symbol(p.name) for p in flat.parameters)
    priority = _priority_function(analysis)
    levels = []
    for level, (rows, candidates, chosen) in enumerate(report.levels):
        if len(candidates) <= len(rows):
            continue
        kept = [v for v in candidates if v not in chosen]
        stand_ins = _stand_ins(system, kept)
        candidates_of_interest = set(chosen) - stand_ins
        varying_set = set()
        for e in rows:                                 # only where the unknown occurs: linear in size
            for v in system.incidence[e]:
                if v in candidates_of_interest and v not in varying_set and \
                        not sympy.diff(system.equations[e], system.symbols[v]).free_symbols <= constant:
                    varying_set.add(v)
        varying = [v for v in chosen if v in varying_set]
        if not varying:
            continue                                   # a constant pivot block is valid everywhere
        if min(priority(v) for v in kept) > max(priority(v) for v in varying):
            continue                                   # only a hinted state could take over: keep the hint
        levels.append((level, rows, candidates, chosen))
    return levels


def _stand_ins(system, kept: list[int]) -> set[int]:
    """Dummies that only stand in for a kept state: der(der(phi)) when `w = der(phi)` holds and
    der(w) is kept. Exchanging the two changes nothing, so they never call for a switch."""
    kept_set = set(kept)
    diff_to_var = system.diff_to_var()
    stand_ins = set()
    for residual in system.equations:
        symbols = [s for s in residual.free_symbols if s in system.index_of]
        if len(symbols) != 2:
            continue
        a, b = (system.index_of[s] for s in symbols)
        for w, dphi in ((a, b), (b, a)):
            if diff_to_var[dphi] >= 0 and abs(sympy.diff(residual, system.symbols[w])) == 1 \
                    and abs(sympy.diff(residual, system.symbols[dphi])) == 1:
                dw, ddphi = system.var_to_diff[w], system.var_to_diff[dphi]
                if dw in kept_set and ddphi >= 0:
                    stand_ins.add(ddphi)
    return stand_ins


def _priority_function(analysis: Analysis):
    diff_to_var = analysis.system.diff_to_var()

    def priority(v: int) -> int:
        return analysis.priorities.get(analysis.system.names[base_variable(analysis.system, v, diff_to_var)], 0)
    return priority


def build_variant(flat: FlatSystem, analysis: Analysis, point: dict[str, float] | None,
                  reduced: ReducedSystem | None = None, report: StructureReport | None = None) -> Variant:
    if reduced is None:
        report = StructureReport()
        reduced = reduce(flat, point=point, report=report, analysis=analysis)
    system = analysis.system
    public = list(reduced.output_names)
    known = set(public)
    internal = [n for n in system.names if n not in known]
    pivots: list[Assignment] = []
    layouts = []
    for level, rows, candidates, chosen in monitored_levels(flat, analysis, report):
        start = len(pivots)
        for i, e in enumerate(rows):
            for j, v in enumerate(candidates):
                pivots.append(Assignment(f"__pivot{level}[{i},{j}]",
                                         sympy.diff(system.equations[e], system.symbols[v])))
        layouts.append((rows, candidates, chosen, start))
    reduced.observables = list(reduced.observables) + pivots
    reduced.output_names = public + internal + [a.target for a in pivots]
    model = lower(reduced)
    offset = len(public) + len(internal)
    priority = _priority_function(analysis)
    model.state_sets = [_state_set(rows, cands, chosen, offset + start, system.names, priority)
                        for rows, cands, chosen, start in layouts]
    return Variant(tuple(reduced.states), reduced, model, report, public)


def _state_set(rows: list[int], candidates: list[int], chosen: list[int], first_output: int,
               names: list[str], priority) -> dict:
    """A monitored level in the runtime's plain form (CompiledModel.state_sets): the level's
    Jacobian entries are outputs first_output... (row-major), candidate positions are grouped by
    priority class, lowest first, as the dummy-derivative choice orders them."""
    order = sorted(range(len(candidates)), key=lambda j: (priority(candidates[j]), j))
    classes: dict[int, list[int]] = {}
    for j in order:
        classes.setdefault(priority(candidates[j]), []).append(j)
    return {"rows": len(rows), "candidates": [names[v] for v in candidates],
            "chosen": [candidates.index(v) for v in chosen], "classes": list(classes.values()),
            "entries": list(range(first_output, first_output + len(rows) * len(candidates)))}


def selection_quality(variant: Variant, values: np.ndarray) -> float:
    """runtime.state_selection_quality of the variant's monitored levels at one output point:
    1 when the current choice is the best one, towards 0 as it degrades."""
    return runtime.state_selection_quality(variant.model.state_sets, values)[0]


def _restart_model(model: runtime.CompiledModel, x_target: np.ndarray, z_guess: np.ndarray) -> runtime.CompiledModel:
    """The same model whose initialization pins the states to `x_target` and solves only alg = 0."""
    restart = copy.copy(model)
    x = ca.SX.sym("x", len(model.state_names))
    z = ca.SX.sym("z", len(model.algebraic_names))
    p = ca.SX.sym("p", len(model.parameter_names))
    t = ca.SX.sym("t")
    _, alg = model.dae(x, z, p, t)
    restart.init = ca.Function("init", [x, z, p, t], [ca.vertcat(alg, x - ca.DM(x_target))])
    restart._init_jacobian = None
    restart.x_guess = [float(v) for v in x_target]
    restart.z_guess = [float(v) for v in z_guess]
    restart.init_residual_labels = []
    return restart


def simulate_dynamic(flat: FlatSystem, analysis: Analysis, first: Variant, stop: float, *, start: float = 0.0,
                     rtol: float = 1e-6, atol: float = 1e-6, points: int = 501, saveat=None,
                     params=None, max_steps: int = 100000, integrator_options=None) -> runtime.Result:
    grid = runtime.output_grid(float(start), float(stop), points, saveat)
    n = len(grid)
    uniform = n > 2 and np.allclose(np.diff(grid), grid[1] - grid[0], rtol=1e-9, atol=0)
    variants = first.siblings
    variants.setdefault(first.states, first)
    workspaces: dict[tuple, _Workspace] = {}
    variant = first
    p = variant.model.parameter_vector(params)
    began = _time.perf_counter()
    point = runtime.consistent_initialization(variant.model, p, grid[0])
    stats = {"init_time": _time.perf_counter() - began, "init_iterations": point.iterations,
             "state_switches": [], "steps": 0, "residual_evaluations": 0, "jacobian_evaluations": 0}
    public = first.public_names
    values = np.empty((len(public), n))
    began = _time.perf_counter()
    last_outputs = runtime._evaluate_outputs(variant.model, point.x.reshape(-1, 1), point.z.reshape(-1, 1),
                                             p, grid[:1])[:, 0]
    values[:, 0] = _public(variant, last_outputs, public)
    x, z = point.x, point.z
    i, span, forced = 0, SEGMENT_POINTS, False
    while i < n - 1:
        j = min(n - 1, i + span)
        work = workspaces.setdefault(variant.states, _Workspace(variant, rtol, atol, max_steps, n, integrator_options))
        try:
            x_end, z_end = runtime._integrate_segment(variant.model, grid, i, j, x, z, p, work.options, uniform,
                                                      work.integrators, work.xs, work.zs, work.counters)
        except runtime.SimulationFailed:
            if span > 1:
                span = 1                  # go point by point so the monitor sees the degradation
                continue
            if forced or not variant.model.state_sets:
                raise
            forced = True                 # switch at the last good point even without a clear margin
            here = dict(zip(variant.model.output_names, last_outputs))
            variant, p, (x, z) = _switch(flat, analysis, variant, variants, here, grid[i], params, stats)
            continue
        forced = False
        segment = grid[i:j + 1]
        zs = runtime.polish_algebraics(variant.model, work.xs[:, i + 1:j + 1], work.zs[:, i + 1:j + 1], p, segment[1:])
        outs = runtime._evaluate_outputs(variant.model, work.xs[:, i + 1:j + 1], zs, p, segment[1:])
        switch_at, qualities = None, []
        for k in range(1, j - i + 1):
            values[:, i + k] = _public(variant, outs[:, k - 1], public)
            if variant.model.state_sets and i + k < n - 1:
                qualities.append(selection_quality(variant, outs[:, k - 1]))
                if qualities[-1] < SWITCH_RATIO:
                    switch_at = k
                    break
        if switch_at is None:
            i, x, z = j, x_end, z_end
            last_outputs = outs[:, -1]
            span = _next_span(qualities)
            continue
        here = dict(zip(variant.model.output_names, outs[:, switch_at - 1]))
        variant, p, (x, z) = _switch(flat, analysis, variant, variants, here, grid[i + switch_at], params, stats)
        last_outputs = outs[:, switch_at - 1]
        i = i + switch_at
    stats["run_time"] = _time.perf_counter() - began
    runtime.check_bounds(first.model, grid, public, values)
    for work in workspaces.values():
        for key in ("steps", "residual_evaluations", "jacobian_evaluations"):
            stats[key] += work.counters.get(key, 0)
    return runtime.Result(grid, public, values, stats, first.model.name)


def _next_span(qualities: list[float]) -> int:
    """Every IDAS restart costs accuracy (measured: ~2.5e-10 per restart at rtol 1e-10 on the
    pendulum), so segments are long; but a segment that runs far past the switch threshold into a
    singular state choice fails. Extrapolate the pivot quality of the last points to the threshold
    and end the next segment a little after it: the switch is then found inside that segment."""
    if len(qualities) < 2 or qualities[-1] >= 1.0:
        return SEGMENT_POINTS
    slope = qualities[-1] - qualities[-2]
    if slope >= 0:
        return SEGMENT_POINTS
    points_left = (qualities[-1] - SWITCH_RATIO) / -slope
    return int(max(2, min(SEGMENT_POINTS, math.ceil(points_left) + 2)))


class _Workspace:
    """Per state set: IDAS options, cached integrators and solution buffers."""

    def __init__(self, variant: Variant, rtol, atol, max_steps, n, integrator_options=None):
        model = variant.model
        self.options = runtime._integrator_options(model, rtol, atol, max_steps, integrator_options)
        self.integrators: dict = {}
        self.xs = np.empty((len(model.state_names), n))
        self.zs = np.empty((len(model.algebraic_names), n))
        self.counters = {v: 0 for v in runtime._COUNTERS.values()}
        self.counters["chunks"] = 0


def _switch(flat, analysis, variant, variants, here: dict, t: float, params, stats):
    # a run that began in C code (`--codegen c`) stays in C code in every state set
    new = _variant_at(flat, analysis, here, variants, c_code=variant.model.metadata.get("codegen") == "c")
    if new.states == variant.states:
        raise runtime.SimulationFailed(f"simulation of {variant.model.name} failed at t = {t:.10g}: the "
                                       "state selection is singular here and no better one exists", t,
                                       "singular state selection")
    stats["state_switches"].append({"time": float(t), "from": list(variant.states), "to": list(new.states)})
    p = new.model.parameter_vector(params)
    x_target = np.array([here[n] for n in new.model.state_names])
    z_guess = np.array([here.get(n, 0.0) for n in new.model.algebraic_names])
    point = runtime.consistent_initialization(_restart_model(new.model, x_target, z_guess), p, t)
    return new, p, (point.x, point.z)


def _variant_at(flat, analysis, values: dict[str, float], cache: dict, c_code: bool = False) -> Variant:
    point = {k: float(v) for k, v in values.items() if not k.startswith("__pivot")}
    selection = select_states(analysis.system, analysis.priorities, flat, point)
    states = tuple(analysis.system.names[v] for v in selection.states)
    if states not in cache:
        built = build_variant(flat, analysis, point)
        built.siblings = cache
        cache[states] = built
    variant = cache[states]
    if c_code and variant.model.metadata.get("codegen") != "c":
        from compiler.ccodegen import compile_c
        compile_c(variant.model)
    return variant


def _public(variant: Variant, column: np.ndarray, public: list[str]) -> np.ndarray:
    index = {n: k for k, n in enumerate(variant.model.output_names)}
    return np.array([column[index[n]] for n in public])
