"""The run loop: from the start to the stop, one integrator call after another.

Each call goes from where the run is to the next segment end (a time event, a breakpoint, the
stop: segments.py) or less, with the relations settled and the event clock set for it; the
integrator says where and why it stopped (integrator.py) and the handler of that kind of stop
(stops.py) moves the run on: past a reached end, a state event, a bound left, a state-set switch,
or after a failure. Nothing else cuts the run: not the output grid, not a progress bar.
"""
from __future__ import annotations

from .event_horizon import event_reach
from .integrator import Call, Integrator
from .progress import Progress
from .relations import settle_relations
from .run_state import RunState
from .segments import output_times, with_clock, within_round_off
from .stops import HANDLERS


def integrate(run: RunState, progress: Progress) -> None:
    """Advance the run (started at RunState.start_at) to the stop."""
    while run.t < run.options.stop:
        end = run.segment_end()
        if within_round_off(run.t, end):      # a located crossing at a segment's end
            run.t = end
            run.end_index += 1
            continue
        run.p = with_clock(run.model, run.p, run.t, end)
        run.p, run.z = settle_relations(run.model, run.p, run.x, run.z, run.t,
                                        live=run.t == run.live_from)     # held over the call
        integrator = run.integrator(run.model)
        call = next_call(run, integrator, end)
        stop = integrator.advance(call)
        for times, xs, zs in stop.samples:
            run.store(run.model, xs, zs, call.p, times)
        HANDLERS[stop.kind](run, call, stop)
        progress.update(run.t)


def next_call(run: RunState, integrator: Integrator, end: float) -> Call:
    """The call from where the run is: the failed call cut short if there is one (RunState.retry),
    else one to the segment's end, or less where crossings are found after a call."""
    retry = run.retry if run.retry is not None and run.retry.t0 == run.t else None
    run.retry = None
    watch = integrator.watch
    ignored = frozenset(i for i, label in enumerate(watch.labels) if label in run.ignored) \
        if watch is not None and run.ignored else frozenset()
    reach = retry.reach if retry is not None else call_reach(run, integrator, end)
    return Call(run.t, run.x, run.z, run.p, reach, output_times(run.grid, run.k, reach), run.scale,
                ignored, horizon=run.horizon, step0=None if retry is None else retry.step0,
                checks=None if retry is None else retry.checks, retry=retry is not None,
                last=reach >= run.options.stop, fresh=at_breakpoint(run.t, run.options.breakpoints))


def at_breakpoint(t: float, breakpoints) -> bool:
    """Whether `t` is one of the caller's breakpoints (to the round-off segments.py merges at)."""
    return any(within_round_off(min(t, float(b)), max(t, float(b))) for b in breakpoints or ())


def call_reach(run: RunState, integrator: Integrator, end: float) -> float:
    """How far a call reaches. An integrator that finds crossings after a call throws away what it
    integrated past the first one: a state-set model's calls reach a little past where its
    indicators are predicted to cross (RunState.horizon: a state set that degrades is integrated
    on, badly, until IDAS fails), a model with state events's calls reach twice the time since the
    last event (event_horizon.py)."""
    if integrator.locates_crossings:
        return end
    t, model = run.t, run.model
    reach = end if not model.state_sets else min(end, t + run.horizon)
    reach = event_reach(model, run.events, t, reach, run.options.start, run.options.stop)
    return end if end - reach <= 1e-9 * (end - t) else reach
