"""Where the driver's segments begin and end: the model's time events and the caller's
breakpoints, the event clock of a segment, the output times inside one, and IDAS's first step."""
from __future__ import annotations

import numpy as np

from .model import CompiledModel
from .options import SimulationOptions
from .watches import time_breakpoints


def first_step(integrator, x, xdot, t0: float, t1: float) -> float:
    """IDAS's own rule for its first step (a thousandth of the distance, then h * der(x) at most
    0.5 in the weighted RMS norm), applied to the segment's end instead of the first output time,
    on which IDAS would make the run depend; rounded down to a power of 2, so that repeated runs
    ask for the same integrator objects. `xdot` is der(x) at the start (integrator.derivative),
    which the run's IDAS call takes as its initial derivative too."""
    model, options = integrator.model, integrator.options
    nx = len(model.state_names)
    h = 1e-3 * (t1 - t0)
    atol = np.asarray(options.get("abstolv", [options.get("abstol", 1e-8)] * nx), dtype=float)[:nx]
    weights = float(options.get("reltol", 1e-6)) * np.abs(np.asarray(x, dtype=float)) + atol
    norm = float(np.sqrt(np.sum((xdot / weights) ** 2) / max(1, nx + len(model.algebraic_names))))
    if np.isfinite(norm) and norm * h > 0.5:
        h = 0.5 / norm
    return float(2.0 ** np.floor(np.log2(h))) if h > 0 and np.isfinite(h) else 1e-3 * (t1 - t0)


def within_round_off(earlier: float, later: float) -> bool:
    """Whether `later` is no more than round-off after `earlier` (one instant for the run)."""
    return later - earlier <= 1e-12 * max(1.0, abs(later))


def segment_ends(model: CompiledModel, p: np.ndarray, options: SimulationOptions) -> list[float]:
    """Where segments end: the model's time events, the caller's breakpoints, the stop time."""
    start, stop = options.start, options.stop
    breaks = set(time_breakpoints(model, p, start, stop))
    breaks |= {float(b) for b in options.breakpoints or () if start < float(b) < stop}
    ends: list[float] = []
    for b in sorted(breaks) + [stop]:            # events closer than round-off are one event
        if ends and within_round_off(ends[-1], b):
            ends[-1] = b
        elif not within_round_off(start, b):
            ends.append(b)
    return ends


def with_clock(model: CompiledModel, p: np.ndarray, t_a: float, t_b: float) -> np.ndarray:
    """p with the model's event clock (compiler/lower/events.py) in the middle of the segment [t_a, t_b]:
    conditions on time hold one value over the whole segment, its ends included."""
    name = model.metadata.get("event_clock")
    if name is None:
        return p
    p = np.array(p, dtype=float)
    p[model.parameter_names.index(name)] = 0.5 * (t_a + t_b)
    return p


def clock_on_switches(model: CompiledModel, p: np.ndarray, times, ends) -> list[tuple[np.ndarray, np.ndarray]]:
    """(which of `times`, parameter vector) pairs covering every time: a sample that falls on a
    switch (a segment end, the stop included) takes the event clock at its own time, so it reports
    the equations' value at that instant, as Dyad's and Modelica's results do, not the value its
    segment held up to it (a square wave switching at the stop); the others keep the segment's
    clock, so that they stay one vectorized evaluation."""
    times = np.asarray(times, dtype=float)
    name = model.metadata.get("event_clock")
    on_end = np.isin(times, np.asarray(ends, dtype=float)) if name is not None and len(times) else None
    if on_end is None or not on_end.any():
        return [(np.ones(len(times), dtype=bool), p)]
    runs = [(~on_end, p)] if (~on_end).any() else []
    row = model.parameter_names.index(name)
    for j in np.nonzero(on_end)[0]:
        own = np.array(p, dtype=float)
        own[row] = times[j]
        runs.append((np.arange(len(times)) == j, own))
    return runs


def output_times(grid: np.ndarray, k: int, reach: float) -> np.ndarray:
    """The output times from grid index k up to `reach`, inclusive: a view of the grid, which
    the native driver takes as it is (a list cost it 45 us a call to build and convert back)."""
    upto = np.searchsorted(grid, reach, side="right")
    times = grid[k:upto]
    assert len(times) == 0 or times[0] > grid[k - 1], "output times run backwards"
    return times
