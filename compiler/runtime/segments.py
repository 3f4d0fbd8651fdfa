"""Where the driver's segments begin and end: the model's time events and the caller's
breakpoints, the event clock of a segment, the output times inside one, and IDAS's first step."""
from __future__ import annotations

import numpy as np

from .model import CompiledModel
from .options import SimulationOptions
from .watches import time_breakpoints


def first_step(integrator, x, z, p, t0: float, t1: float) -> float:
    """IDAS's own rule for its first step (a thousandth of the distance, then h * der(x) at most
    0.5 in the weighted RMS norm), applied to the segment's end instead of the first output time,
    on which IDAS would make the run depend; rounded down to a power of 2, so that repeated runs
    ask for the same integrator objects."""
    model, options = integrator.model, integrator.options
    nx = len(model.state_names)
    h = 1e-3 * (t1 - t0)
    try:
        xdot = np.asarray(model.dae(x, z, p, t0)[0], dtype=float).reshape(-1)
    except RuntimeError:
        xdot = np.zeros(nx)
    atol = np.asarray(options.get("abstolv", [options.get("abstol", 1e-8)] * nx), dtype=float)[:nx]
    weights = float(options.get("reltol", 1e-6)) * np.abs(np.asarray(x, dtype=float)) + atol
    norm = float(np.sqrt(np.sum((xdot / weights) ** 2) / max(1, nx + len(model.algebraic_names))))
    if np.isfinite(norm) and norm * h > 0.5:
        h = 0.5 / norm
    return float(2.0 ** np.floor(np.log2(h))) if h > 0 and np.isfinite(h) else 1e-3 * (t1 - t0)


def segment_ends(model: CompiledModel, p: np.ndarray, options: SimulationOptions) -> list[float]:
    """Where segments end: the model's time events, the caller's breakpoints, the stop time."""
    start, stop = options.start, options.stop
    breaks = set(time_breakpoints(model, p, start, stop))
    breaks |= {float(b) for b in options.breakpoints or () if start < float(b) < stop}
    ends: list[float] = []
    for b in sorted(breaks) + [stop]:            # events closer than round-off are one event
        if ends and b - ends[-1] <= 1e-12 * max(1.0, abs(b)):
            ends[-1] = b
        elif b - start > 1e-12 * max(1.0, abs(b)):
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


def clock_on_switches(model: CompiledModel, ps: np.ndarray, times, ends) -> np.ndarray:
    """ps (one parameter column per output time) with the event clock at the output's own time
    where that time is a segment end: a sample that falls on a switch (the stop included) reports
    the equations' value at that instant, as Dyad's and Modelica's results do, not the value its
    segment held up to it (a square wave switching at the stop). Other samples keep their
    segment's clock, so a segment's outputs stay one vectorized evaluation."""
    name = model.metadata.get("event_clock")
    if name is None or not len(times):
        return ps
    on_end = np.isin(np.asarray(times, dtype=float), np.asarray(ends, dtype=float))
    if not on_end.any():
        return ps
    ps = np.array(ps, dtype=float)
    ps[model.parameter_names.index(name), on_end] = np.asarray(times, dtype=float)[on_end]
    return ps


def segment_times(grid: np.ndarray, k: int, end: float) -> tuple[list[float], int]:
    """The output times from grid index k up to `end`, inclusive (IDAS's grid for the segment,
    ending at `end`), and how many of them are grid points."""
    upto = np.searchsorted(grid, end, side="right")
    times = [float(v) for v in grid[k:upto]]
    assert not times or times[0] > grid[k - 1], "output times run backwards"
    m = len(times)
    if not times or times[-1] != end:
        times.append(float(end))
    return times, m
