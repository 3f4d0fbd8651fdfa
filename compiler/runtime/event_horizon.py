"""How far one IDAS call of a model with state events reaches.

The driver looks for crossings after a call, so everything a call integrates past the first
crossing is thrown away (and integrated on the wrong branch of a locked relation, relations.py),
and events come in cascades (one relation's switch makes the next cross nanoseconds later). So a
call reaches GROWTH times as far as the time since the last event (since the start before the
first), at least SHORTEST of the span: short calls right after an event, geometrically longer ones
while none comes. Models with few events pay for it with restarts of IDAS. The measurements that
chose these constants: docs/numerics.md, "How far an IDAS call reaches".
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
    last = next((e["time"] for e in reversed(events) if e["time"] <= t), None)
    if last is None:
        ahead = max(GROWTH * (t - start), FIRST_REACH * (stop - start))
    else:
        ahead = max(GROWTH * (t - last), SHORTEST * (stop - start))
    reach = t + ahead
    return end if reach >= end else reach
