"""The one simulation driver: consistent initialization, then one segment loop for every run.

Segments end only where the model says so (time events, from `model.time_events` and the given
breakpoints) or where a watched crossing stops IDAS (a declared bound: the run fails there; a
degrading state set: the run switches there, when the caller provides a `StateSetSwitcher`).
Nothing else cuts the run: not the output grid, not a progress bar. State events of the model are
located by IDAS inside a segment and logged in the Result.
"""
from __future__ import annotations

import time as _time
from typing import Mapping, Protocol, Sequence

import numpy as np

from .checks import bound_violation, check_divergence, state_scales
from .errors import SimulationFailed, SimulationInterrupted
from .idas import integrator_options
from .initialization import consistent_initialization, restart_point
from .integrator import COUNTERS, IdasIntegrator
from .model import CompiledModel
from .options import SimulationOptions
from .outputs import evaluate_outputs, polish_algebraics
from .progress import Progress
from .result import Result
from .static import solve_static
from .watches import build_watch, time_breakpoints


class StateSetSwitcher(Protocol):
    """Provides the model of another state set where the current one degrades (the compiler's
    dynamic state selection). `public_names` are the signals every variant reports."""
    public_names: list[str]

    def switch(self, model: CompiledModel, values: Mapping[str, float], t: float) -> CompiledModel: ...


class _Run:
    """The state of one run: where it is, which model (state set) it integrates, what it collected."""

    def __init__(self, model: CompiledModel, options: SimulationOptions, switcher):
        self.options = options
        self.switcher = switcher
        self.public = list(switcher.public_names) if switcher is not None else list(model.output_names)
        self.grid = options.grid()
        self.values = np.full((len(self.public), len(self.grid)), np.nan)
        self.counters = {v: 0 for v in COUNTERS.values()}
        self.counters["segments"] = 0
        self.events: list[dict] = []
        self.switches: list[dict] = []
        self.integrators: dict[int, tuple] = {}
        self.model = model

    def integrator(self, model: CompiledModel):
        key = id(model)
        if key not in self.integrators:
            watch = build_watch(model)
            opts = integrator_options(model, self.options.rtol, self.options.atol,
                                      self.options.max_steps, self.options.idas_options())
            public_index = [model.output_index(n) for n in self.public]
            self.integrators[key] = (model, IdasIntegrator(model, opts, watch), watch, public_index)
        return self.integrators[key][1:]

    def store(self, model: CompiledModel, xs, zs, p, times, first: int, public_index) -> None:
        """Outputs at the grid points first, first + 1, ..., which are `times`."""
        n = len(times)
        if n == 0:
            return
        zs = polish_algebraics(model, xs[:, :n], zs[:, :n], p, np.asarray(times[:n]))
        outs = evaluate_outputs(model, xs[:, :n], zs, p, np.asarray(times[:n]))
        self.values[:, first:first + n] = outs[public_index]

    def add(self, counters: Mapping) -> None:
        for key, value in counters.items():
            self.counters[key] = self.counters.get(key, 0) + value
        self.counters["segments"] += 1


def simulate(model: CompiledModel, stop: float | None = None, *, options: SimulationOptions | None = None,
             switcher: StateSetSwitcher | None = None, **settings) -> Result:
    """Initialize consistently at the start, integrate to the stop, evaluate the outputs.

    Either pass `options` or the same settings as keywords (stop, start, points, saveat, rtol, atol,
    params, max_steps, max_step, breakpoints, integrator_options, progress)."""
    if options is None:
        options = SimulationOptions(stop=stop, **settings)
    elif stop is not None or settings:
        raise TypeError("pass either options or keyword settings, not both")
    options = options.validated()
    run = _Run(model, options, switcher)
    p = model.parameter_vector(options.params)
    stats: dict = {"compile_time": model.compile_time}
    began = _time.perf_counter()
    point = consistent_initialization(model, p, options.start)
    stats.update(init_time=_time.perf_counter() - began, init_iterations=point.iterations,
                 init_residual=point.residual)
    began = _time.perf_counter()
    progress = Progress(options.show_progress(), options.start, options.stop)
    t = options.start
    try:
        if not model.state_names:
            run.values[:] = solve_static(model, run.grid, p, point.z, run.counters, progress)[
                [model.output_index(n) for n in run.public]]
        else:
            t = _integrate(run, model, p, point, progress)
    except KeyboardInterrupt:
        raise SimulationInterrupted(f"interrupted at t = {t:.10g}", float(t), "interrupted") from None
    finally:
        progress.close()
    stats["run_time"] = _time.perf_counter() - began
    stats.update(run.counters)
    stats["state_switches"] = run.switches
    units = model.metadata.get("units") or {}
    return Result(run.grid, run.public, run.values, stats, model.name,
                  units={n: units[n] for n in run.public if n in units},
                  events=run.events, switches=run.switches)


def _integrate(run: _Run, model: CompiledModel, p: np.ndarray, point, progress: Progress) -> float:
    options, grid = run.options, run.grid
    breaks = sorted(set(time_breakpoints(model, p, options.start, options.stop))
                    | {float(b) for b in options.breakpoints or () if options.start < b < options.stop})
    ends = [b for b in breaks if options.start < b < options.stop] + [options.stop]
    scale = state_scales(model, point.x)
    run.values[:, 0] = _outputs_at(run, model, point.x, point.z, p, grid[0])
    t, x, z = options.start, point.x, point.z
    k = 1                                                # next grid index to fill
    end_index = 0
    while t < options.stop:
        end = ends[end_index]
        times, m = _segment_times(grid, k, end, inclusive=True)
        integrator, watch, public_index = run.integrator(model)
        segment = integrator.run(t, times, x, z, p)
        if segment.stop is None:
            run.add(segment.counters)
            _log_events(run, watch, segment.events)
            check_divergence(model, np.asarray(times), segment.xs, scale)
            run.store(model, segment.xs, segment.zs, p, times[:m], k, public_index)
            k += m
            t, x, z = end, segment.xs[:, -1], segment.zs[:, -1]
            end_index += 1
            progress.update(t)
            continue
        t_stop, row = segment.stop
        kind, what = watch.labels[row]
        # the crossing ended the IDAS call: integrate again up to it, without stopping
        times, m = _segment_times(grid, k, t_stop, inclusive=False)
        again = integrator.run(t, times, x, z, p, stopping=False)
        run.add(again.counters)
        _log_events(run, watch, again.events)
        check_divergence(model, np.asarray(times), again.xs, scale)
        run.store(model, again.xs, again.zs, p, times[:m], k, public_index)
        k += m
        x_stop, z_stop = again.xs[:, -1], again.zs[:, -1]
        values = dict(zip(model.output_names, _all_outputs(model, x_stop, z_stop, p, t_stop)))
        if kind == "bound":
            name, key, bound = what
            raise bound_violation(model, name, key, bound, values[name], t_stop)
        model, x, z, p = _switch(run, model, values, t_stop, p, x_stop, z_stop, what)
        t = t_stop
        progress.update(t)
    return t


def _segment_times(grid: np.ndarray, k: int, end: float, inclusive: bool) -> tuple[list[float], int]:
    """The output times from grid index k up to `end` (IDAS's grid for the segment, ending at
    `end`), and how many of them are grid points."""
    upto = np.searchsorted(grid, end, side="right" if inclusive else "left")
    times = [float(v) for v in grid[k:upto]]
    m = len(times)
    if not times or times[-1] != end:
        times.append(float(end))
    return times, m


def _switch(run: _Run, model: CompiledModel, values: Mapping[str, float], t: float, p, x, z, level: int):
    """Continue in the state set that the switcher chooses at this point."""
    current = model.state_sets[level]
    dummies = ", ".join(current["candidates"][j] for j in current["chosen"])
    if run.switcher is None:
        reason = (f"its state set ({', '.join(model.state_names)}) degrades here (the pivot block of "
                  f"the dummy derivatives {dummies} is close to singular); this model carries one "
                  f"state set: simulate it with dyadc, which switches state sets")
        raise SimulationFailed(f"simulation of {model.name} stopped at t = {t:.10g}: {reason}", t, reason)
    new = run.switcher.switch(model, values, t)
    if new.state_names == model.state_names:
        reason = "the state selection is singular here and no better one exists"
        raise SimulationFailed(f"simulation of {model.name} failed at t = {t:.10g}: {reason}", t, reason)
    run.switches.append({"time": float(t), "from": list(model.state_names), "to": list(new.state_names),
                         "degraded": dummies})
    p_new = new.parameter_vector(run.options.params)
    x_target = np.array([values[n] for n in new.state_names])
    z_guess = np.array([values.get(n, 0.0) for n in new.algebraic_names])
    point = restart_point(new, p_new, t, x_target, z_guess)
    return new, point.x, point.z, p_new


def _log_events(run: _Run, watch, events) -> None:
    for t, row in events:
        kind, what = watch.labels[row]
        if kind == "event":
            run.events.append({"time": float(t), "event": what})


def _all_outputs(model: CompiledModel, x, z, p, t: float) -> np.ndarray:
    xs, zs = np.asarray(x).reshape(-1, 1), np.asarray(z).reshape(-1, 1)
    zs = polish_algebraics(model, xs, zs, p, np.array([t]))
    return evaluate_outputs(model, xs, zs, p, np.array([t]))[:, 0]


def _outputs_at(run: _Run, model: CompiledModel, x, z, p, t: float) -> np.ndarray:
    index = [model.output_index(n) for n in run.public]
    return _all_outputs(model, x, z, p, t)[index]


def output_grid(start: float, stop: float, points: int, saveat: Sequence[float] | None) -> np.ndarray:
    return SimulationOptions(stop=stop, start=start, points=points, saveat=saveat).validated().grid()

