"""What the run does where a call stops (run_loop.py): one handler per kind of stop (Stop.kind).
Each takes the run (RunState), the call and its stop, and moves the run on or raises."""
from __future__ import annotations

import warnings

from .checks import BoundWarning, bound_violation, bound_warning, state_scales
from .crossings import predicted_stay
from .errors import SimulationFailed
from .integrator import FAILED, REACHED, UNCONFIRMED, Call, Stop
from .relations import has_locks, sliding
from .run_state import RunState
from .switching import all_outputs, explained, switch_state_set

MAX_EVENTS_AT_ONE_TIME = 50
MAX_RETRIES = 200                # shortened calls after IDAS failures, per run


def on_reached(run: RunState, call: Call, stop: Stop) -> None:
    """The call reached its end: go on from there."""
    if stop.horizon is not None:
        run.horizon = max(stop.horizon, run.shortest_reach)
    end = run.segment_end()
    run.move(stop.t, stop.x, stop.z)
    run.restarts_here = 0
    if stop.t >= end:
        run.end_index += 1
    if call.retry and run.model.state_sets and run.switcher is not None:
        # IDAS failed a little further on: take the state set pivoting prefers here, if it is
        # another one, before going into the failure again
        values = dict(zip(run.model.output_names, all_outputs(run.model, run.x, run.z, run.p, run.t)))
        if run.switcher.switch(run.model, values, run.t).state_names != run.model.state_names:
            run.model, run.x, run.z, run.p = switch_state_set(run, run.model, values, run.t, run.p,
                                                              run.x, run.z, 0)


def on_unconfirmed(run: RunState, call: Call, stop: Stop) -> None:
    """A crossing the call saw is not there when looked at closely: go on from where it looked."""
    run.move(stop.t, stop.x, stop.z)


def on_failed(run: RunState, call: Call, stop: Stop) -> None:
    """The integrator failed: once more with the relations live, or a shorter call, or the end."""
    if not live_relations(run):
        retry_before_failure(run, stop)


def live_relations(run: RunState) -> bool:
    """Whether the call is made again with its relations live (relations.py): a locked branch may
    have no value past its crossing (sqrt of a level below zero); live, the call crosses over and
    the crossing is located."""
    if run.live_from == run.t or not has_locks(run.model):
        return False
    run.live_from = run.t
    return True


def retry_before_failure(run: RunState, stop: Stop) -> None:
    """A watched crossing (a bound, a degrading state set) may come before the failure and explain
    it: the call again, cut before the failure (Stop.retry). A bound shows in the first retry; a
    degrading state set may need a few, each ending nearer the failure (switches are proposed
    there). Without such a call, the failure ends the run."""
    model = run.model
    again = run.t in run.forced_ends and (not model.state_sets or len(run.forced_ends) > MAX_RETRIES)
    if again or stop.retry is None:
        raise explained(model, stop.failure)
    run.retry = stop.retry
    run.forced_ends.add(stop.retry.reach)
    run.horizon = min(run.horizon, stop.retry.reach - run.t)


def crossing_values(run: RunState, stop: Stop) -> dict:
    """The outputs at a crossing, after counting it among the crossings without time advancing
    (a condition that keeps flipping there is chattering: the run stops)."""
    outputs = stop.outputs if stop.outputs is not None else \
        all_outputs(run.model, stop.x, stop.z, run.p, stop.t, stop.settled)
    values = dict(zip(run.model.output_names, outputs))
    here = stop.t - run.t <= 1e-12 * max(1.0, abs(run.t))
    run.restarts_here = run.restarts_here + 1 if here else 0
    if run.restarts_here > MAX_EVENTS_AT_ONE_TIME:
        reason = f"the condition {stop.what} switches back and forth without time advancing (chattering)"
        raise SimulationFailed(f"simulation of {run.model.name} stopped at t = {stop.t:.10g}: {reason}",
                               stop.t, reason)
    return values


def on_bound(run: RunState, call: Call, stop: Stop) -> None:
    """A declared bound left: the end of the run (bounds="error"), or a warning, once per bound (a
    value that stays outside, or comes back and leaves again, is not located again)."""
    values = crossing_values(run, stop)
    name, key, bound = stop.what
    if run.options.bounds == "error":
        raise bound_violation(run.model, name, key, bound, values[name], stop.t)
    message = bound_warning(run.model, name, key, bound, values[name], stop.t)
    warnings.warn(message, BoundWarning, stacklevel=3)
    run.bounds_left.append({"time": float(stop.t), "variable": name, "bound": key,
                            "limit": float(bound), "value": float(values[name])})
    run.ignored.add((stop.kind, stop.what))
    run.move(stop.t, stop.x, stop.z)


def on_event(run: RunState, call: Call, stop: Stop) -> None:
    """A state event: logged; the run restarts there (its relations settle at the next call)."""
    crossing_values(run, stop)
    for _, what, direction in sorted(((stop.row, stop.what, stop.direction),) + stop.together,
                                     key=lambda crossing: crossing[0]):
        run.events.append({"time": float(stop.t), "event": what,
                           "direction": "rising" if direction > 0 else "falling"})
    stuck = sliding(run.model, run.events)        # a sliding mode (relations.py)
    if stuck is not None:
        raise stuck
    run.move(stop.t, stop.x, stop.z)


def on_state_set(run: RunState, call: Call, stop: Stop) -> None:
    """A state set degrades: the run goes on in the one the switcher chooses there."""
    values = crossing_values(run, stop)
    t = stop.t
    run.durations[tuple(run.model.state_names)] = t - run.last_switch
    run.model, x, z, run.p = switch_state_set(run, run.model, values, t, run.p, stop.x, stop.z, stop.what)
    run.move(t, x, z)
    run.scale = state_scales(run.model, x)      # other states: their scale from the switch point
    # every call that ends before the next switch costs a restart, and every step past it is
    # thrown away: predict the stay in this state set from the switches so far
    run.intervals.append(t - run.last_switch)
    run.horizon = max(predicted_stay(run.intervals, run.durations.get(tuple(run.model.state_names))),
                      run.shortest_reach)
    run.last_switch = t


HANDLERS = {REACHED: on_reached, UNCONFIRMED: on_unconfirmed, FAILED: on_failed,
            "bound": on_bound, "event": on_event, "state set": on_state_set}
