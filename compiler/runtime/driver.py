"""The one simulation driver: consistent initialization, then one segment loop for every run.

Segments end where the model says so (time events, from `model.time_events` and the given
breakpoints) and where a watched function crosses zero (watches.py): a state event of the model
(the run restarts there, the event is logged), a declared bound (the run fails there, naming it),
a degrading state set (the run switches there, when the caller provides a `StateSetSwitcher`).
Watched functions are evaluated at CHECKS_PER_SEGMENT check times that depend only on the segment,
never on the output grid, and a crossing is located by a root search on short IDAS runs. Nothing
else cuts the run: not the output grid, not a progress bar.
"""
from __future__ import annotations

import time as _time
import warnings

import numpy as np

from . import interrupts
from .checks import BoundWarning, bound_violation, bound_warning, check_divergence, state_scales
from .crossings import before_failure, first_crossing, locate, next_horizon, predicted_stay, watched_values
from .errors import SimulationFailed, SimulationInterrupted
from .event_horizon import event_reach
from .initialization import InitialPoint, consistent_initialization
from .model import CompiledModel
from .options import SimulationOptions
from .outputs import signals_at
from .progress import Progress
from .relations import has_locks, settle_relations, sliding
from .result import Result
from .run_state import RunState, StateSetSwitcher, switched_factor
from .segments import first_step, segment_ends, segment_times, with_clock
from .static import solve_static
from .switching import all_outputs, explained, switch_state_set

CHECKS_PER_SEGMENT = 200
MAX_EVENTS_AT_ONE_TIME = 50
MAX_RETRIES = 200                # shortened segments after IDAS failures, per run
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
    run = RunState(model, options, switcher)
    p = model.parameter_vector(options.params)
    run.parameters = model.named_parameters(p)
    run.ends = segment_ends(model, p, options)
    p = with_clock(model, p, options.start, run.ends[0])
    stats: dict = {"compile_time": model.compile_time}
    began = _time.perf_counter()
    point = consistent_initialization(model, p, options.start)
    p, settled_z = settle_relations(model, p, point.x, point.z, options.start)
    point = InitialPoint(point.x, settled_z, point.iterations, point.residual)
    stats.update(init_time=_time.perf_counter() - began, init_iterations=point.iterations,
                 init_residual=point.residual)
    began = _time.perf_counter()
    progress = Progress(options.show_progress(), options.start, options.stop)
    with interrupts.watching():
        return _run_watched(run, model, p, point, progress, stats, began)


def _run_watched(run, model, p, point, progress, stats, began) -> Result:
    try:
        if not model.state_names:
            run.values[:] = solve_static(model, run.grid, p, point.z, run.counters, progress)[
                [model.output_index(n) for n in run.public]]
        else:
            _integrate(run, model, p, point, progress)
            run.finish()
    except KeyboardInterrupt:
        raise SimulationInterrupted(f"interrupted at t = {run.t:.10g}", float(run.t),
                                    "interrupted") from None
    except SimulationFailed as failure:
        failure.partial = _partial_result(run, model)
        raise
    except Exception:
        if interrupts.pending:              # CasADi's wrapper turns Ctrl-C into other errors
            raise SimulationInterrupted(f"interrupted at t = {run.t:.10g}", float(run.t),
                                        "interrupted") from None
        raise
    finally:
        progress.close()
    stats["run_time"] = _time.perf_counter() - began
    stats.update(run.counters)
    stats["state_switches"] = run.switches
    if run.bounds_left:                   # declared bounds the run left and went on (bounds="warn")
        stats["bounds_left"] = run.bounds_left
    if run.switches:                      # what IDAS ran at from the first switch on
        stats["rtol_after_first_switch"] = run.options.rtol / switched_factor(run.options.rtol)
    return _result(run, model, len(run.grid), stats)


def _result(run: RunState, model: CompiledModel, n: int, stats: dict) -> Result:
    """The first n output times of the run as a Result."""
    units = model.metadata.get("units") or {}
    return Result(run.grid[:n], run.public, run.values[:, :n], stats, model.name,
                  units={name: units[name] for name in run.public if name in units},
                  events=run.events, switches=run.switches, parameters=run.parameters)


def _partial_result(run: RunState, model: CompiledModel) -> Result | None:
    """The output times the run had reached when it failed, as a Result (None if not even one)."""
    try:
        run.finish()
    except Exception:                       # the failure itself may have left bad points behind
        return None
    filled = ~np.isnan(run.values).all(axis=0) if run.values.size else np.zeros(0, dtype=bool)
    n = int(np.argmin(filled)) if not filled.all() else len(filled)
    return _result(run, model, n, dict(run.counters)) if n else None


def _integrate(run: RunState, model: CompiledModel, p: np.ndarray, point, progress: Progress) -> float:
    """The segment loop: IDAS runs from (t, x, z) to the next segment end (a time event, the stop),
    or, in a model with state sets, to a reach predicted from its indicators; it restarts there, at
    a located crossing or after a switch. (Integrating again from the last restart instead of
    restarting where a call without crossing ended was measured: on the pendulums it took 1.2-2x
    the steps for at most 2x less error, and no gain where the states switch.)"""
    options, grid, ends = run.options, run.grid, run.ends
    scale = state_scales(model, point.x)
    run.values[:, 0] = _outputs_at(run, model, point.x, point.z, p, grid[0])
    t, x, z = options.start, point.x, point.z
    k = 1                                                # next grid index to fill
    end_index = 0
    restarts_here = 0
    live_from = None                                     # a call from here evaluates relations live
    while t < options.stop:
        run.t = t
        end = ends[end_index]
        if end - t <= 1e-12 * max(1.0, abs(end)):      # a located crossing at a segment's end
            t = end
            end_index += 1
            continue
        p = with_clock(model, p, t, end)
        p, z = settle_relations(model, p, x, z, t, live=t == live_from)   # held over the call
        integrator, watch, public_index = run.integrator(model)
        retry = run.retry if run.retry is not None and run.retry[0] == t else None
        run.retry = None
        if retry is not None:
            # the call that failed, cut at its last check before the failure: the same check
            # times and first step, so that what follows does not depend on where IDAS stopped
            reach, checks, step0 = retry[1:]
            xdot = None                       # the IDAS call computes it from (x, z)
        else:
            # a state set that degrades is integrated on, badly, until IDAS fails: one call
            # reaches only a little past where its indicators are predicted to cross (_next_horizon)
            reach = end if not model.state_sets else min(end, t + run.horizon)
            reach = event_reach(model, run.events, t, reach, options.start, options.stop)   # past crossings: thrown away
            if end - reach <= 1e-9 * (end - t):
                reach = end
            checks = [] if watch is None else list(np.linspace(t, reach, CHECKS_PER_SEGMENT + 1)[1:])
            xdot = integrator.derivative(x, z, p, t)
            step0 = first_step(integrator, x, xdot, t, reach)
        outputs, m = segment_times(grid, k, reach)
        times = sorted(set(outputs) | set(checks))
        try:
            # every run starts from a point that solves the algebraic equations already (the
            # initialization, a located crossing, the end of a segment): IDAS's own
            # initial-condition search would make the run depend on the first output time
            segment = integrator.run(t, times, x, z, p, consistent=True, step0=step0, xdot=xdot)
        except SimulationFailed as failure:
            if live_from != t and has_locks(model):
                live_from = t             # the locked branch failed past a crossing: once more live
                continue
            # a bound crossing before the failure shows in the first retry; a degrading state set
            # may need a few, each ending nearer the failure (switches are proposed there)
            again = t in run.forced_ends and (not model.state_sets or len(run.forced_ends) > MAX_RETRIES)
            shorter = None if again else before_failure(watch, checks, failure, t)
            if shorter is None:
                raise explained(model, failure) from None
            # a watched crossing (a bound, a degrading state set) may come before the failure and
            # explain it: run again up to the last check time IDAS got past
            run.retry = (t, shorter, [c for c in checks if c <= shorter], step0)
            run.forced_ends.add(shorter)
            run.horizon = min(run.horizon, shorter - t)
            continue
        run.add(segment.counters)
        watched = None if watch is None else watched_values(watch, t, x, z, p, times, checks, segment)
        crossing = None if watch is None else first_crossing(model, watch, t, p, times, checks,
                                                              segment, watched,
                                                              {i for i, label in enumerate(watch.labels)
                                                               if label in run.ignored}
                                                              if run.ignored else frozenset())
        reached = len(times) if crossing is None else int(np.searchsorted(times, crossing[0]))
        check_divergence(model, np.asarray(times[:reached]), segment.xs[:, :reached], scale)
        n_out = m if crossing is None else int(np.searchsorted(outputs[:m], crossing[1], side="right"))
        at = np.searchsorted(times, outputs[:n_out])
        run.store(model, segment.xs[:, at], segment.zs[:, at], p, outputs[:n_out], k, public_index)
        k += n_out
        if crossing is None:
            if model.state_sets:
                run.horizon = max(next_horizon(watch, t, checks, watched, run.horizon), run.shortest_reach)
            t, x, z = reach, segment.xs[:, -1], segment.zs[:, -1]
            restarts_here = 0
            if reach >= end:
                end_index += 1
            if retry is not None and model.state_sets and run.switcher is not None:
                # IDAS failed a little further on: take the state set pivoting prefers here, if
                # it is another one, before going into the failure again
                values = dict(zip(model.output_names, all_outputs(model, x, z, p, t)))
                if run.switcher.switch(model, values, t).state_names != model.state_names:
                    model, x, z, p = switch_state_set(run, model, values, t, p, x, z, 0)
            progress.update(t)
            continue
        t_right, t_left, row = crossing
        kind, what = watch.labels[row]
        if kind == "state set":
            # any point past the crossing serves: the switch chooses the best set there and the
            # new set's indicator starts far from zero (switch_indicators), so no root search
            right = times.index(t_right)
            x_cross, z_cross, t_cross = segment.xs[:, right], segment.zs[:, right], t_right
            n_right = int(np.searchsorted(outputs[:m], t_right, side="right"))
            at = np.searchsorted(times, outputs[n_out:n_right])
            run.store(model, segment.xs[:, at], segment.zs[:, at], p, outputs[n_out:n_right], k,
                      public_index)
            k += n_right - n_out
        else:
            left = times.index(t_left) if t_left in times else -1
            x_left, z_left = (segment.xs[:, left], segment.zs[:, left]) if left >= 0 else (x, z)
            t_cross, x_cross, z_cross, crossed = locate(run.add, integrator, watch, row, t_left, t_right,
                                                         x_left, z_left, p)
            # outputs between the check before the crossing and the crossing were computed past a
            # kink the segment stepped over: recompute them up to the crossing
            k = _refill(run, model, integrator, p, public_index, k, t_left, t_cross, x_left, z_left)
            if not crossed:
                # the crossing was the long run's own error: a run from the check before it does
                # not cross; go on from there
                t, x, z = t_cross, x_cross, z_cross
                progress.update(t)
                continue
        values = dict(zip(model.output_names, all_outputs(model, x_cross, z_cross, p, t_cross)))
        restarts_here = restarts_here + 1 if t_cross - t <= 1e-12 * max(1.0, abs(t)) else 0
        if restarts_here > MAX_EVENTS_AT_ONE_TIME:
            reason = f"the condition {what} switches back and forth without time advancing (chattering)"
            raise SimulationFailed(f"simulation of {model.name} stopped at t = {t_cross:.10g}: {reason}",
                                   t_cross, reason)
        if kind == "bound":
            name, key, bound = what
            if run.options.bounds == "error":
                raise bound_violation(model, name, key, bound, values[name], t_cross)
            # once per bound: a value that stays outside, or comes back and leaves again, is not
            # located again (each located crossing costs a restart)
            message = bound_warning(model, name, key, bound, values[name], t_cross)
            warnings.warn(message, BoundWarning, stacklevel=2)
            run.bounds_left.append({"time": float(t_cross), "variable": name, "bound": key,
                                    "limit": float(bound), "value": float(values[name])})
            run.ignored.add(watch.labels[row])
            x, z = x_cross, z_cross
        elif kind == "event":
            # rising: the condition's left side minus its right side went from below zero to above
            before = float(np.asarray(watch.function(x_left, z_left, p, t_left))[row, 0])
            run.events.append({"time": float(t_cross), "event": what,
                               "direction": "rising" if before <= 0 else "falling"})
            stuck = sliding(model, run.events)        # a sliding mode (relations.py)
            if stuck is not None:
                raise stuck
            x, z = x_cross, z_cross
        else:
            run.durations[tuple(model.state_names)] = t_cross - run.last_switch
            model, x, z, p = switch_state_set(run, model, values, t_cross, p, x_cross, z_cross, what)
            scale = state_scales(model, x)        # other states: their scale from the switch point
            # every call that ends before the next switch costs a restart, and every step past
            # it is thrown away: predict the stay in this state set from the switches so far
            run.intervals.append(t_cross - run.last_switch)
            run.horizon = max(predicted_stay(run.intervals, run.durations.get(tuple(model.state_names))),
                              run.shortest_reach)
            run.last_switch = t_cross
        t = t_cross
        progress.update(t)
    return t


def _refill(run: RunState, model, integrator, p, public_index, k: int, t_a: float, t_b: float,
            x_a, z_a) -> int:
    """Outputs at the grid times in (t_a, t_b) recomputed from the point at t_a; returns the next
    grid index to fill."""
    grid = run.grid
    first = max(k, int(np.searchsorted(grid, t_a, side="right")))
    last = int(np.searchsorted(grid, t_b, side="right"))
    if last > first:
        times = [float(v) for v in grid[first:last]]
        xdot = integrator.derivative(x_a, z_a, p, t_a)
        segment = integrator.run(t_a, times, x_a, z_a, p, consistent=True,
                                 step0=first_step(integrator, x_a, xdot, t_a, t_b), xdot=xdot)
        run.add(segment.counters)
        run.store(model, segment.xs, segment.zs, p, times, first, public_index)
    return max(k, last)


def _outputs_at(run: RunState, model: CompiledModel, x, z, p, t: float) -> np.ndarray:
    index = [model.output_index(n) for n in run.public]
    return signals_at(model, np.asarray(x).reshape(-1, 1), np.asarray(z).reshape(-1, 1), p, np.array([t]),
                      index)[:, 0]

