"""Golden CSV files and the per-signal tube comparison.

A signal passes when |y - y_golden| <= atol_s + rtol_s * |y_golden| at every compared time; its
violation ratio is max |y - y_golden| / (atol_s + rtol_s * |y_golden|), so <= 1 passes.
"""
from __future__ import annotations

import csv
import math
import os
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np

from compiler.errors import DyadError
from compiler.runtime.writers import atomic_write
from compiler.testing.golden_cases import TestCase

GRID_RTOL = 1e-12           # time grids that agree this closely are the same grid


@dataclass
class Golden:
    time: np.ndarray
    columns: dict[str, np.ndarray]
    path: str


@dataclass
class SignalCheck:
    name: str
    ratio: float                    # max violation ratio; inf for NaN or a missing value
    time: float | None = None       # where the ratio is largest
    value: float | None = None
    expected: float | None = None
    tolerance: float | None = None  # atol_s + rtol_s * |expected| there
    problem: str | None = None      # a failure that is not a number (missing column, ...)

    @property
    def passed(self) -> bool:
        return self.problem is None and self.ratio <= 1.0

    def message(self, label: str) -> str:
        if self.problem:
            return f"{label}: {self.name}: {self.problem}"
        return (f"{label}: signal {self.name} leaves its tube at t = {self.time:.6g}: "
                f"got {self.value:.10g}, golden {self.expected:.10g}, "
                f"|difference| = {abs(self.value - self.expected):.3g} > tolerance {self.tolerance:.3g} "
                f"(ratio {self.ratio:.3g})")


@dataclass
class CaseReport:
    case: TestCase
    signals: list[SignalCheck] = field(default_factory=list)
    finals: list[SignalCheck] = field(default_factory=list)
    initials: list[SignalCheck] = field(default_factory=list)      # expect.initial, at the start
    notes: list[str] = field(default_factory=list)
    error: str | None = None        # the case could not run (compile/simulate/golden file)
    seconds: float = 0.0

    @property
    def passed(self) -> bool:
        return self.error is None and all(c.passed for c in self.signals + self.initials + self.finals)

    def failures(self) -> list[str]:
        if self.error:
            return [self.error]
        out = [c.message(self.case.label) for c in self.signals if not c.passed]
        out += [c.message(self.case.label + " (initial value)") for c in self.initials if not c.passed]
        out += [c.message(self.case.label + " (final value)") for c in self.finals if not c.passed]
        return out

    def format(self, verbose: bool = True) -> str:
        head = f"{'PASS' if self.passed else 'FAIL'} {self.case.label} ({self.seconds:.1f} s)"
        lines = [head] + [f"  note: {n}" for n in list(self.case.notes) + self.notes]
        if self.error:
            lines.append(f"  error: {self.error}")
            return "\n".join(lines)
        if verbose:
            rows = self.signals + self.initials + self.finals
            width = max((len(c.name) for c in rows), default=6) + 10
            lines.append(f"  {'signal':<{width}} {'max ratio':>10}  {'at t':>8}  result")
            for kind, checks in (("", self.signals), (" [initial]", self.initials),
                                 (" [final]", self.finals)):
                for c in checks:
                    at = "" if c.time is None else f"{c.time:8.4g}"
                    ratio = "-" if c.problem else f"{c.ratio:10.3g}"
                    lines.append(f"  {c.name + kind:<{width}} {ratio:>10}  {at:>8}  "
                                 f"{'ok' if c.passed else 'FAIL'}")
        for message in self.failures():
            lines.append(f"  {message}")
        return "\n".join(lines)


# ---------------------------------------------------------------------------------- files

def golden_path(golden_dir: str | os.PathLike, case: TestCase) -> str:
    return os.path.join(os.fspath(golden_dir), f"{case.model}.{case.name}.csv")


def read_golden(path: str) -> Golden:
    try:
        with open(path, newline="", encoding="utf-8") as handle:
            rows = list(csv.reader(handle))
    except OSError as err:
        raise DyadError(f"cannot read golden file {path}: {err.strerror}") from None
    if len(rows) < 3 or not rows[0] or rows[0][0] != "time":
        raise DyadError(f"golden file {path} is not a result CSV (a `time` column first and at "
                        f"least two rows)")
    header = rows[0]
    try:
        data = np.array([[float(v) for v in row] for row in rows[1:] if row], dtype=float)
    except ValueError as err:
        raise DyadError(f"golden file {path} holds a value that is not a number ({err})") from None
    if data.ndim != 2 or data.shape[1] != len(header):
        raise DyadError(f"golden file {path}: rows do not all have {len(header)} columns")
    if np.any(np.diff(data[:, 0]) <= 0):
        raise DyadError(f"golden file {path}: time column is not strictly increasing")
    columns = {name: data[:, k] for k, name in enumerate(header) if k > 0}
    return Golden(data[:, 0], columns, path)


def write_golden(path: str, time: np.ndarray, columns: Mapping[str, np.ndarray]) -> None:
    """Time first, then the columns, %.17g (round-trips doubles); atomically: written to a
    sibling temporary that replaces `path` only when complete."""
    names = list(columns)
    data = np.vstack([np.asarray(time, dtype=float)] + [np.asarray(columns[n], dtype=float)
                                                         for n in names]).T
    def write(temp: str) -> None:
        with open(temp, "w", encoding="utf-8", newline="") as out:
            writer = csv.writer(out, lineterminator="\n")
            writer.writerow(["time"] + names)
            writer.writerows(["%.17g" % value for value in row] for row in data)
    atomic_write(path, write)


# ----------------------------------------------------------------------------- comparison

def same_grid(a: np.ndarray, b: np.ndarray) -> bool:
    scale = max(float(np.max(np.abs(a))), float(np.max(np.abs(b))), 1.0)
    return a.shape == b.shape and bool(np.all(np.abs(a - b) <= GRID_RTOL * scale))


def compare_signals(case: TestCase, time: np.ndarray, values: Mapping[str, np.ndarray],
                    golden: Golden) -> tuple[list[SignalCheck], list[str]]:
    """Check every expected signal of the case; returns the checks and notes (grid handling)."""
    notes: list[str] = []
    time = np.asarray(time, dtype=float)
    mask = np.ones(time.shape, dtype=bool)
    interpolate = not same_grid(time, golden.time)
    if interpolate:
        # Linear interpolation adds its own error (O(dt^2 y'')) to the difference: regenerate the
        # golden on the case's grid (--accept) when the tube is tight.
        span = max(golden.time[-1] - golden.time[0], 1.0)
        mask = (time >= golden.time[0] - GRID_RTOL * span) & (time <= golden.time[-1] + GRID_RTOL * span)
        notes.append(f"result grid ({len(time)} points) differs from the golden grid "
                     f"({len(golden.time)} points): golden interpolated linearly"
                     + ("" if mask.all() else f"; {int((~mask).sum())} result times outside the "
                                               f"golden's time span are not compared"))
    checks = []
    for name in case.signals:
        if name not in golden.columns:
            checks.append(SignalCheck(name, math.inf, problem=f"no column `{name}` in {golden.path} "
                                                              f"(regenerate it with --accept)"))
            continue
        if name not in values:
            checks.append(SignalCheck(name, math.inf, problem="the model has no such signal"))
            continue
        expected = golden.columns[name]
        if interpolate:
            expected = np.interp(time[mask], golden.time, expected)
        checks.append(tube_check(name, time[mask], np.asarray(values[name], dtype=float)[mask],
                                 expected, *case.tube(name)))
    return checks, notes


def tube_check(name: str, time: np.ndarray, value: np.ndarray, expected: np.ndarray,
               atol: float, rtol: float) -> SignalCheck:
    tolerance = atol + rtol * np.abs(expected)
    difference = np.abs(value - expected)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(difference == 0.0, 0.0, difference / tolerance)
    ratio = np.where(np.isfinite(value) & np.isfinite(expected), ratio, np.inf)
    if ratio.size == 0:
        return SignalCheck(name, math.inf, problem="no time in common with the golden")
    k = int(np.argmax(ratio))
    return SignalCheck(name, float(ratio[k]), float(time[k]), float(value[k]), float(expected[k]),
                       float(tolerance[k]))


def compare_finals(case: TestCase, time: np.ndarray, values: Mapping[str, np.ndarray]) -> list[SignalCheck]:
    """`expect.final`: each value at the stop time, within its signal's tube."""
    return _compare_at(case, case.final, -1, time, values)


def compare_initials(case: TestCase, time: np.ndarray, values: Mapping[str, np.ndarray]) -> list[SignalCheck]:
    """`expect.initial`: each value at the start time (after initialization), within its tube."""
    return _compare_at(case, case.expect_initial, 0, time, values)


def _compare_at(case: TestCase, expected_values: Mapping[str, float], index: int,
                time: np.ndarray, values: Mapping[str, np.ndarray]) -> list[SignalCheck]:
    checks = []
    at = slice(index, None if index == -1 else index + 1)
    for name, expected in expected_values.items():
        if name not in values:
            checks.append(SignalCheck(name, math.inf, problem="the model has no such signal"))
            continue
        value = np.asarray(values[name], dtype=float)[at]
        checks.append(tube_check(name, np.asarray(time, dtype=float)[at], value,
                                 np.array([expected]), *case.tube(name)))
    return checks


def signal_values(result, names: Sequence[str]) -> dict[str, np.ndarray]:
    """The named signals a result has (missing ones are reported by the comparison)."""
    return {n: result[n] for n in names if n in result}
