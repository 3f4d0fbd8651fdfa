"""Repeated timing within a time budget, and the record of one work-precision point."""
from __future__ import annotations

import statistics
from dataclasses import dataclass, field
from typing import Callable


@dataclass
class Point:
    """One tolerance of one contender on one problem. `status` is "ok", "failed" or "skipped"."""
    tolerance: float
    status: str
    times: list[float] = field(default_factory=list)
    errors: dict[str, float] = field(default_factory=dict)    # named error measures
    note: str = ""

    @property
    def time(self) -> float:
        return statistics.median(self.times) if self.times else float("nan")

    @property
    def runs(self) -> int:
        return len(self.times)


@dataclass
class Budget:
    """How long one contender may spend on one problem, and how many repeats a point gets."""
    total_s: float
    repeats: int = 5
    repeat_window_s: float = 10.0     # the repeats of one point together should fit in this

    def repeats_for(self, single_run_s: float) -> int:
        if single_run_s <= 0:
            return self.repeats
        return max(1, min(self.repeats, int(self.repeat_window_s / single_run_s)))


def predict_next(times: list[float], tolerance_ratio: float = 10.0) -> float:
    """Expected run time at the next (tighter) tolerance from the growth of the last two points."""
    if not times:
        return 0.0
    if len(times) == 1:
        return times[-1] * 3.0
    growth = max(times[-1] / times[-2], 1.0) if times[-2] > 0 else 3.0
    return times[-1] * growth


def timed_runs(run: Callable[[], tuple[float, dict]], repeats: int) -> tuple[list[float], dict]:
    """Call `run` `repeats` times; it returns (seconds, output). Keeps the last output."""
    times, output = [], {}
    for _ in range(repeats):
        seconds, output = run()
        times.append(seconds)
    return times, output
