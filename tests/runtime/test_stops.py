"""Each kind of stop handled alone (compiler/runtime/stops.py), on a run placed by hand, and the run
loop driven by an integrator that finds crossings itself (the Integrator interface's other side:
every call reaches the segment's end, crossings come back as stops)."""
from __future__ import annotations

import warnings

import numpy as np
import pytest

from compiler import api
from compiler.lower.to_casadi import lower
from compiler.runtime import SimulationFailed, SimulationOptions
from compiler.runtime.checks import BoundWarning
from compiler.runtime.initialization import consistent_initialization
from compiler.runtime.integrator import FAILED, REACHED, UNCONFIRMED, Call, Stop
from compiler.runtime.progress import Progress
from compiler.runtime.relations import SLIDING_EVENTS
from compiler.runtime.run_loop import integrate
from compiler.runtime.run_state import RunState
from compiler.runtime.segments import segment_ends
from compiler.runtime.stops import (HANDLERS, MAX_EVENTS_AT_ONE_TIME, on_bound, on_event, on_failed,
                                    on_reached, on_unconfirmed)
from tests.runtime.runtime_systems import draining

X_MIN = ("x", "min", 0.0)            # draining()'s bound, as its watch labels it


def started(model, make_integrator=None, **settings) -> RunState:
    """A run of `model` at its consistent start, as driver.simulate leaves it for the loop."""
    options = SimulationOptions(**settings).validated()
    run = RunState(model, options, None) if make_integrator is None else \
        RunState(model, options, None, make_integrator)
    p = model.parameter_vector(options.params)
    run.ends = segment_ends(model, p, options)
    point = consistent_initialization(model, p, options.start)
    run.start_at(p, point.x, point.z)
    return run


def call_from(run: RunState, reach: float) -> Call:
    return Call(run.t, run.x, run.z, run.p, reach, [], run.scale)


def test_a_bound_left_ends_the_run_with_bounds_error():
    run = started(lower(draining()), stop=3.0, points=2, bounds="error")
    stop = Stop("bound", 1.0, np.array([-1e-9]), np.zeros(0), row=0, what=X_MIN)
    with pytest.raises(SimulationFailed) as failure:
        on_bound(run, call_from(run, 3.0), stop)
    assert failure.value.variable == "x" and failure.value.time_reached == 1.0
    assert run.t == 0.0


def test_a_bound_left_is_warned_of_logged_and_no_longer_watched():
    run = started(lower(draining()), stop=3.0, points=2)
    stop = Stop("bound", 1.0, np.array([-1e-9]), np.zeros(0), row=0, what=X_MIN)
    with pytest.warns(BoundWarning):
        on_bound(run, call_from(run, 3.0), stop)
    assert [(b["variable"], b["bound"], b["time"]) for b in run.bounds_left] == [("x", "min", 1.0)]
    assert run.ignored == {("bound", X_MIN)}
    assert (run.t, float(run.x[0])) == (1.0, -1e-9)


def test_the_next_call_does_not_watch_a_bound_already_warned_of():
    run = started(lower(draining()), stop=3.0, points=2)
    run.ignored.add(("bound", X_MIN))
    calls = []
    run.make_integrator = recording(calls, [Stop(REACHED, 3.0, np.array([-2.0]), np.zeros(0))])
    integrate(run, Progress(False, 0.0, 3.0))
    assert [call.ignored for call in calls] == [frozenset({0})]


def test_an_event_is_logged_and_the_run_goes_on_from_it():
    run = started(lower(draining()), stop=3.0, points=2)
    on_event(run, call_from(run, 3.0), Stop("event", 0.5, np.array([0.5]), np.zeros(0), what="x > 0.5",
                                            direction=1))
    assert run.events == [{"time": 0.5, "event": "x > 0.5", "direction": "rising"}]
    assert run.t == 0.5 and run.restarts_here == 0


def test_one_condition_flipping_within_a_nanosecond_is_a_sliding_mode():
    run = started(lower(draining()), stop=3.0, points=2)
    run.events = [{"time": 0.5 + 1e-12 * i, "event": "v > 0"} for i in range(SLIDING_EVENTS - 1)]
    run.t = 0.5 + 1e-12 * SLIDING_EVENTS
    with pytest.raises(SimulationFailed, match="sliding mode"):
        on_event(run, call_from(run, 3.0), Stop("event", run.t + 1e-12, run.x, run.z, what="v > 0"))


def test_crossings_without_time_advancing_are_chattering():
    run = started(lower(draining()), stop=3.0, points=2)
    run.restarts_here = MAX_EVENTS_AT_ONE_TIME
    with pytest.raises(SimulationFailed, match="chattering"):
        on_event(run, call_from(run, 3.0), Stop("event", 0.0, run.x, run.z, what="x > 0.5"))
    assert run.events == []


def test_a_call_that_reached_a_segment_end_moves_to_the_next_segment():
    run = started(lower(draining()), stop=3.0, points=2, breakpoints=[2.0])
    assert run.ends == [2.0, 3.0]
    run.horizon = 0.5
    on_reached(run, call_from(run, 1.0), Stop(REACHED, 1.0, np.array([0.0]), np.zeros(0), horizon=1e-9))
    assert (run.t, run.end_index, run.horizon) == (1.0, 0, run.shortest_reach)
    on_reached(run, call_from(run, 2.0), Stop(REACHED, 2.0, np.array([-1.0]), np.zeros(0)))
    assert (run.t, run.end_index, run.horizon) == (2.0, 1, run.shortest_reach)


def test_an_unconfirmed_crossing_only_moves_the_run():
    run = started(lower(draining()), stop=3.0, points=2)
    run.restarts_here = 3
    on_unconfirmed(run, call_from(run, 3.0), Stop(UNCONFIRMED, 0.25, np.array([0.75]), np.zeros(0)))
    assert (run.t, float(run.x[0]), run.restarts_here, run.end_index) == (0.25, 0.75, 3, 0)


def test_a_failure_without_a_shorter_call_ends_the_run():
    run = started(lower(draining()), stop=3.0, points=2)
    failure = SimulationFailed("simulation of Draining failed at t = 0.7: IDA_CONV_FAIL", 0.7, "IDA_CONV_FAIL")
    with pytest.raises(SimulationFailed) as raised:
        on_failed(run, call_from(run, 3.0), Stop(FAILED, 0.0, run.x, run.z, failure=failure))
    assert raised.value is failure


def test_a_failure_with_a_shorter_call_is_retried_up_to_it():
    run = started(lower(draining()), stop=3.0, points=2)
    failure = SimulationFailed("failed at t = 0.7", 0.7, "IDA_CONV_FAIL")
    shorter = Call(0.0, run.x, run.z, run.p, 0.6, [], run.scale, checks=(0.3, 0.6), step0=1e-3, retry=True)
    run.horizon = 1.0
    on_failed(run, call_from(run, 3.0), Stop(FAILED, 0.0, run.x, run.z, failure=failure, retry=shorter))
    assert run.retry is shorter and run.forced_ends == {0.6} and run.horizon == 0.6
    run.move(0.6, run.x, run.z)                  # the shorter call reached its end; the next one fails
    again = Call(0.6, run.x, run.z, run.p, 0.65, [], run.scale, checks=(0.65,), step0=1e-3, retry=True)
    with pytest.raises(SimulationFailed):        # from a cut end of a model without state sets: the end
        on_failed(run, call_from(run, 3.0), Stop(FAILED, 0.6, run.x, run.z, failure=failure, retry=again))


TANK = """
  parameter k::Real = 1.0
  variable h::Real
relations
  initial h = 1.0
  der(h) = if h > 0 then -k * sqrt(h) else 0"""


def test_a_failure_with_locked_relations_is_tried_once_more_live(tmp_path):
    path = tmp_path / "Torricelli.dyad"
    path.write_text(f"component Torricelli\n{TANK}\nend\n", encoding="utf-8")
    run = started(api.compile(str(path)).model, stop=4.0, points=9)
    failure = SimulationFailed("failed at t = 2.1", 2.1, "IDA_RES_FAIL")
    stop = Stop(FAILED, 0.0, run.x, run.z, failure=failure)
    on_failed(run, call_from(run, 4.0), stop)
    assert run.live_from == 0.0 and run.retry is None
    with pytest.raises(SimulationFailed):
        on_failed(run, call_from(run, 4.0), stop)


def recording(calls: list, stops: list):
    """An integrator factory whose integrators record their calls and return `stops` in turn."""
    class Scripted:
        locates_crossings = True

        def __init__(self, model, options, watch, tally):
            self.watch = watch

        def advance(self, call: Call) -> Stop:
            calls.append(call)
            return stops.pop(0)
    return Scripted


def test_an_integrator_that_finds_crossings_is_called_to_each_segment_end():
    calls: list[Call] = []
    exact = lambda t: np.array([1.0 - t])                               # noqa: E731
    stops = [Stop("bound", 1.0, exact(1.0), np.zeros(0), [([0.5, 1.0], np.array([[0.5, 0.0]]), np.zeros((0, 2)))],
                  row=0, what=X_MIN),
             Stop(REACHED, 2.0, exact(2.0), np.zeros(0), [([1.5, 2.0], np.array([[-0.5, -1.0]]), np.zeros((0, 2)))]),
             Stop(REACHED, 3.0, exact(3.0), np.zeros(0), [([2.5, 3.0], np.array([[-1.5, -2.0]]), np.zeros((0, 2)))])]
    run = started(lower(draining()), recording(calls, stops), stop=3.0, points=7, breakpoints=[2.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BoundWarning)
        integrate(run, Progress(False, 0.0, 3.0))
    run.finish()
    assert [(c.t0, c.reach, c.outputs.tolist()) for c in calls] == [(0.0, 2.0, [0.5, 1.0, 1.5, 2.0]),
                                                           (1.0, 2.0, [1.5, 2.0]), (2.0, 3.0, [2.5, 3.0])]
    assert [c.ignored for c in calls] == [frozenset(), frozenset({0}), frozenset({0})]
    np.testing.assert_array_equal(run.values[0], [1.0, 0.5, 0.0, -0.5, -1.0, -1.5, -2.0])
    assert run.bounds_left[0]["time"] == 1.0 and run.t == 3.0 and not stops


def test_every_kind_of_stop_has_a_handler():
    assert set(HANDLERS) == {REACHED, UNCONFIRMED, FAILED, "bound", "event", "state set"}


def test_a_model_with_one_state_set_runs_without_a_switcher():
    from compiler.runtime import default_switcher
    assert default_switcher(lower(draining())) is None


def test_a_bound_counts_when_left_and_a_state_event_both_ways(tmp_path):
    from compiler.runtime.crossings import root_directions
    from compiler.runtime.watches import build_watch
    path = tmp_path / "Torricelli.dyad"
    path.write_text(f"component Torricelli\n{TANK}\nend\n", encoding="utf-8")
    assert root_directions(build_watch(lower(draining()))).tolist() == [-1]
    assert root_directions(build_watch(api.compile(str(path)).model)).tolist() == [0]
