"""What IDAS watches during a run, assembled from the compiled model: the model's own state events
(both directions), its declared bounds (stop), the indicators of its state sets (stop), and the
time events computed from the parameters."""
from __future__ import annotations

import math

import casadi as ca
import numpy as np

from .checks import bound_indicators
from .errors import ModelInputError
from .integrator import Watch
from .model import CompiledModel
from .state_sets import switch_indicators

MAX_TIME_EVENTS = 1_000_000


def build_watch(model: CompiledModel) -> Watch | None:
    x, z, p, t = model.symbols()
    rows: list[ca.SX] = []
    kinds: list[str] = []
    labels: list[tuple] = []
    if model.events is not None and model.events.numel_out():
        relations = model.events(x, z, p, t)
        for i in range(relations.shape[0]):
            label = model.event_labels[i] if i < len(model.event_labels) else f"event {i}"
            # IDAS reports crossings from + to - only: watch both signs to see both directions
            rows += [relations[i], -relations[i]]
            kinds += ["record", "record"]
            labels += [("event", label), ("event", label)]
    outputs = model.outputs(x, z, p, t) if model.output_names else ca.SX(0, 1)
    bounds, bound_labels = bound_indicators(model, outputs)
    for i, label in enumerate(bound_labels):
        rows.append(bounds[i])
        kinds.append("stop")
        labels.append(("bound", label))
    indicators = switch_indicators(model.state_sets, outputs)
    for level in range(indicators.shape[0]):
        rows.append(indicators[level])
        kinds.append("stop")
        labels.append(("state set", level))
    if not rows:
        return None
    function = ca.Function("watch", [x, z, p, t], [ca.vertcat(*rows)], ["x", "z", "p", "t"], ["zero"])
    return Watch(function, tuple(kinds), tuple(labels))


def time_breakpoints(model: CompiledModel, p: np.ndarray, start: float, stop: float) -> list[float]:
    """Times in (start, stop) where a time-only expression of the model is non-smooth (a step, a
    pulse edge, a table breakpoint): offset + k * period for each pair model.time_events gives."""
    if model.time_events is None:
        return []
    offsets, periods = (np.asarray(v, dtype=float).reshape(-1) for v in model.time_events(p))
    times: set[float] = set()
    for offset, period in zip(offsets, periods):
        if not math.isfinite(offset):
            continue
        if not (math.isfinite(period) and period > 0):
            if start < offset < stop:
                times.add(float(offset))
            continue
        first = math.ceil((start - offset) / period)
        last = math.floor((stop - offset) / period)
        if last - first + 1 + len(times) > MAX_TIME_EVENTS:
            raise ModelInputError(f"model {model.name} has more than {MAX_TIME_EVENTS} time events "
                                  f"between {start:g} and {stop:g} (period {period:g})")
        times.update(float(v) for v in offset + period * np.arange(first, last + 1)
                     if start < v < stop)
    return sorted(times)
