"""What the driver watches during a run, assembled from the compiled model: the model's own state
events, its declared bounds, the indicators of its state sets (zero-crossing functions of
x, z, p, t), and the time events computed from the parameters."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from .checks import bound_indicators
from .errors import ModelInputError
from .model import CompiledModel
from .outputs import PointwiseEvaluator
from .state_sets import switch_indicators

MAX_TIME_EVENTS = 1_000_000


@dataclass
class Watch:
    """Zero-crossing functions with what a sign change of each row means: ("event", label) a state
    event of the model, ("bound", (name, key, bound)) a declared bound (positive inside),
    ("state set", level) a monitored state set (positive while it holds)."""
    function: ca.Function              # (x, z, p, t) -> column
    labels: tuple[tuple, ...]
    atol: float = 0.0                  # the absolute tolerance that widens the bounds (watched_rows)
    _maps: dict = field(default_factory=dict, repr=False)

    def values(self, xs: np.ndarray, zs: np.ndarray, p: np.ndarray, times) -> np.ndarray:
        """(rows x times), one vectorized call."""
        if "evaluator" not in self._maps:       # numpy in and out, p shared (outputs.py)
            self._maps["evaluator"] = PointwiseEvaluator(self.function)
        return self._maps["evaluator"].evaluate(xs, zs, p, times)[0]


def build_watch(model: CompiledModel, atol: float = 0.0) -> Watch | None:
    x, z, p, t = symbols = model.symbols()
    rows, labels = watched_rows(model, symbols, atol)
    if not labels:
        return None
    function = ca.Function("watch", [x, z, p, t], [rows], ["x", "z", "p", "t"], ["zero"])
    return Watch(function, tuple(labels), float(atol))


def watched_rows(model: CompiledModel, symbols: tuple, atol) -> tuple[ca.SX, list[tuple]]:
    """The watched zero functions of `symbols` (x, z, p, t: model.symbols()) as one column, and
    their labels (Watch); `atol` (a number, or a symbol for a compiled watch that takes it as
    input) widens the bounds."""
    x, z, p, t = symbols
    rows: list[ca.SX] = []
    labels: list[tuple] = []
    if model.events is not None and model.events.numel_out():
        relations = model.events(x, z, p, t)
        for i in range(relations.shape[0]):
            label = model.event_labels[i] if i < len(model.event_labels) else f"event {i}"
            # IDAS reports crossings from + to - only: watch both signs to see both directions
            rows.append(relations[i])
            labels.append(("event", label))
    outputs = model.outputs(x, z, p, t) if model.output_names else ca.SX(0, 1)
    bounds, bound_labels = bound_indicators(model, outputs, atol)
    for i, label in enumerate(bound_labels):
        rows.append(bounds[i])
        labels.append(("bound", label))
    indicators = switch_indicators(model.state_sets, outputs)
    for level in range(indicators.shape[0]):
        rows.append(indicators[level])
        labels.append(("state set", level))
    return (ca.vertcat(*rows) if rows else ca.SX(0, 1)), labels


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
