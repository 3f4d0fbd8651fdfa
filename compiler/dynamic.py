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
import time as _time
from dataclasses import dataclass, field

import casadi as ca
import numpy as np
import sympy

from compiler import runtime
from compiler.flat import FlatSystem
from compiler.lower_casadi import lower
from compiler.structure.dummy_derivatives import _numeric_greedy, base_variable
from compiler.structure.reduce import Analysis, StructureReport, reduce, select_states
from compiler.structure.reduced import Assignment, ReducedSystem

SWITCH_RATIO = 0.5
SEGMENT_POINTS = 20


@dataclass
class LevelMonitor:
    rows: list[int]
    candidates: list[int]
    chosen: list[int]
    entry_outputs: list[int]        # output indices of the rows x candidates entries, row-major


@dataclass
class Variant:
    states: tuple[str, ...]
    reduced: ReducedSystem
    model: runtime.CompiledModel
    report: StructureReport
    public_names: list[str]
    monitors: list[LevelMonitor] = field(default_factory=list)


def build_variant(flat: FlatSystem, analysis: Analysis, point: dict[str, float] | None) -> Variant:
    report = StructureReport()
    reduced = reduce(flat, point=point, report=report, analysis=analysis)
    system = analysis.system
    public = list(reduced.output_names)
    known = set(public)
    internal = [n for n in system.names if n not in known]
    pivots: list[Assignment] = []
    layouts = []
    constant = set(sympy.Symbol(p.name) for p in flat.parameters)
    for level, (rows, candidates, chosen) in enumerate(report.levels):
        if len(candidates) <= len(rows):
            continue
        chosen_entries = [sympy.diff(system.equations[e], system.symbols[v]) for e in rows for v in chosen]
        if all(entry.free_symbols <= constant for entry in chosen_entries):
            continue                                   # valid everywhere: never switch
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
    monitors = [LevelMonitor(rows, cands, chosen, list(range(offset + start, offset + start + len(rows) * len(cands))))
                for rows, cands, chosen, start in layouts]
    return Variant(tuple(reduced.states), reduced, model, report, public, monitors)


def needs_switch(variant: Variant, values: np.ndarray, priority) -> bool:
    for m in variant.monitors:
        matrix = values[m.entry_outputs].reshape(len(m.rows), len(m.candidates))
        best = _best_columns(matrix, m, priority)
        current = [m.candidates.index(v) for v in m.chosen]
        if sorted(best) == sorted(current):
            continue
        if _smallest_singular(matrix[:, current]) < SWITCH_RATIO * _smallest_singular(matrix[:, best]):
            return True
    return False


def _best_columns(matrix: np.ndarray, monitor: LevelMonitor, priority) -> list[int]:
    """The pivoted choice at this point, as positions in `monitor.candidates`."""
    order = sorted(range(len(monitor.candidates)), key=lambda j: (priority(monitor.candidates[j]), j))
    chosen, _ = _numeric_greedy(order, matrix[:, order], lambda j: priority(monitor.candidates[j]),
                                len(monitor.rows))
    return chosen


def _smallest_singular(block: np.ndarray) -> float:
    if block.size == 0:
        return 0.0
    return float(np.linalg.svd(block, compute_uv=False)[-1])


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
                     params=None, max_steps: int = 100000) -> runtime.Result:
    grid = runtime.output_grid(float(start), float(stop), points, saveat)
    diff_to_var = analysis.system.diff_to_var()

    def priority(v: int) -> int:
        return analysis.priorities.get(analysis.system.names[base_variable(analysis.system, v, diff_to_var)], 0)

    variants = {first.states: first}
    variant = first
    p = variant.model.parameter_vector(params)
    began = _time.perf_counter()
    point = runtime.consistent_initialization(variant.model, p, grid[0])
    stats = {"init_time": _time.perf_counter() - began, "init_iterations": point.iterations,
             "state_switches": [], "steps": 0, "residual_evaluations": 0, "jacobian_evaluations": 0}
    public = first.public_names
    values = np.empty((len(public), len(grid)))
    began = _time.perf_counter()
    i = 0
    first_values = runtime._evaluate_outputs(variant.model, point.x.reshape(-1, 1), point.z.reshape(-1, 1), p, grid[:1])
    values[:, 0] = _public(variant, first_values[:, 0], public)
    last_outputs = first_values[:, 0]
    span = SEGMENT_POINTS
    forced = False
    while i < len(grid) - 1:
        j = min(len(grid) - 1, i + span)
        segment = grid[i:j + 1]
        try:
            xs, zs, counters = runtime._integrate(variant.model, segment, p, point, rtol, atol, max_steps, 1,
                                                  runtime._Progress(False, segment[0], segment[-1]), None)
        except runtime.SimulationFailed:
            if span > 1:
                span = 1                  # go point by point so the monitor sees the degradation
                continue
            if forced or not variant.monitors:
                raise
            forced = True                 # switch at the last good point even without a clear margin
            here = dict(zip(variant.model.output_names, last_outputs))
            variant, p, point = _switch(flat, analysis, variant, variants, here, grid[i], params, stats)
            continue
        forced = False
        for key in ("steps", "residual_evaluations", "jacobian_evaluations"):
            stats[key] += counters.get(key, 0)
        outs = runtime._evaluate_outputs(variant.model, xs, zs, p, segment)
        switch_at = None
        for k in range(1, len(segment)):
            values[:, i + k] = _public(variant, outs[:, k], public)
            if variant.monitors and (j < len(grid) - 1 or k < len(segment) - 1) \
                    and needs_switch(variant, outs[:, k], priority):
                switch_at = k
                break
        if switch_at is None:
            i = j
            last_outputs = outs[:, -1]
            point = runtime.InitialPoint(xs[:, -1], zs[:, -1], 0, 0.0)
            span = SEGMENT_POINTS
            continue
        here = dict(zip(variant.model.output_names, outs[:, switch_at]))
        variant, p, point = _switch(flat, analysis, variant, variants, here, segment[switch_at], params, stats)
        last_outputs = None
        i = i + switch_at
    stats["run_time"] = _time.perf_counter() - began
    return runtime.Result(grid, public, values, stats, first.model.name)


def _switch(flat, analysis, variant, variants, here: dict, t: float, params, stats):
    new = _variant_at(flat, analysis, here, variants)
    if new.states == variant.states:
        raise runtime.SimulationFailed(f"simulation of {variant.model.name} failed at t = {t:.10g}: the "
                                       "state selection is singular here and no better one exists", t,
                                       "singular state selection")
    stats["state_switches"].append({"time": float(t), "from": list(variant.states), "to": list(new.states)})
    p = new.model.parameter_vector(params)
    x_target = np.array([here[n] for n in new.model.state_names])
    z_guess = np.array([here.get(n, 0.0) for n in new.model.algebraic_names])
    point = runtime.consistent_initialization(_restart_model(new.model, x_target, z_guess), p, t)
    return new, p, point


def _variant_at(flat, analysis, values: dict[str, float], cache: dict) -> Variant:
    point = {k: float(v) for k, v in values.items() if not k.startswith("__pivot")}
    selection = select_states(analysis.system, analysis.priorities, flat, point)
    states = tuple(analysis.system.names[v] for v in selection.states)
    if states not in cache:
        cache[states] = build_variant(flat, analysis, point)
    return cache[states]


def _public(variant: Variant, column: np.ndarray, public: list[str]) -> np.ndarray:
    index = {n: k for k, n in enumerate(variant.model.output_names)}
    return np.array([column[index[n]] for n in public])
