"""How far one IDAS call of a model with state events reaches.

The driver looks for crossings after a call, at its check times, so everything a call integrates
past the first crossing is thrown away (and integrated on the wrong branch of a locked relation,
relations.py). A call that always reaches the next time event or the stop costs, over a run with
N events, about N / 2 times the whole span: an op-amp amplifier clipping a 1 kHz sine (about 700
events in 0.1 s) took 27.1 million IDAS steps at rtol 1e-10 so (4.3 million at 1e-6). Events
also come in cascades (one relation's switch makes the next cross nanoseconds later). So a call
reaches GROWTH times as far as the time since the last event (since the start before the first),
at least SHORTEST of the span: short calls right after an event, geometrically longer ones while
none comes. The op-amp's 0.1 s then take 633 k steps at 1e-10 (212 k at 1e-6).

Alternatives measured on its first 12 ms at rtol 1e-10 (IDAS steps, root searches included):
four median intervals between the recent events ahead 159 k, two 98 k, one 93 k; growth 2x
from 1e-4 of the span 64 k (3x: 65 k, 4x: 88 k; from 1e-3 of the span: 76 k, from 1e-5: 81 k).
The price is paid by models with few events: every call that ends without a crossing restarts
IDAS cold. The saturated controller and the draining tank of tests/runtime/test_events.py (101
output points, rtol 1e-8) took 664 and 497 steps with every call reaching the stop, 991 and 872
so (the shares of the root searches unchanged).
"""
from __future__ import annotations

FIRST_REACH = 0.05           # of the span: the first call, before any event
GROWTH = 2.0                 # a call reaches this many times the time since the last event
SHORTEST = 1e-4              # of the span: no call is cut shorter


def event_reach(model, events: list[dict], t: float, end: float, start: float, stop: float) -> float:
    """The end of the next IDAS call from t, at most `end`; `end` itself for a model without
    state events."""
    if model.events is None or not model.events.numel_out():
        return end
    # events are recorded in the order of their times: the last one not after t, found from the end
    # (a scan of all of them at every call grew with the run: the op-amp has ~700 and ~7,000 calls)
    last = next((e["time"] for e in reversed(events) if e["time"] <= t), None)
    if last is None:
        ahead = max(GROWTH * (t - start), FIRST_REACH * (stop - start))
    else:
        ahead = max(GROWTH * (t - last), SHORTEST * (stop - start))
    reach = t + ahead
    return end if reach >= end else reach
