"""Tolerance sweeps (work-precision data) and speed-ups at matched error."""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from suite.contenders import Failed, contenders_for
from suite.problems import Problem
from suite.timing import Budget, Point, predict_next, timed_runs

FULL_TOLERANCES = tuple(10.0 ** -k for k in range(3, 11))       # 1e-3 ... 1e-10
QUICK_TOLERANCES = (1e-3, 1e-5, 1e-7, 1e-9)


@dataclass
class Curve:
    contender: str
    points: list[Point] = field(default_factory=list)
    setup_note: str = ""

    def ok(self) -> list[Point]:
        return [p for p in self.points if p.status == "ok" and p.errors.get("error", 0) > 0]


@dataclass
class ProblemRun:
    problem: Problem
    curves: list[Curve]
    unavailable: dict[str, str]
    seconds: float = 0.0


def sweep(contender, problem: Problem, tolerances, budget: Budget, log) -> Curve:
    curve = Curve(contender.name)
    spent = 0.0
    try:                                   # warm-up: imports, lazy construction, caches
        began = time.perf_counter()
        contender.solve(tolerances[0], tolerances[0] * problem.atol_ratio)
        spent += time.perf_counter() - began
    except Failed:
        pass                               # the real point at this tolerance records the failure
    times: list[float] = []
    for tol in tolerances:
        predicted = predict_next(times)
        if spent + predicted > budget.total_s:
            curve.points.append(Point(tol, "skipped", note=f"predicted {predicted:.0f} s per run exceeds the "
                                                           f"remaining budget ({budget.total_s - spent:.0f} s)"))
            continue
        began = time.perf_counter()
        try:
            first, signals = contender.solve(tol, tol * problem.atol_ratio)
        except Failed as err:
            spent += time.perf_counter() - began
            curve.points.append(Point(tol, "failed", note=str(err)[:300]))
            log(f"  {contender.name:12s} tol {tol:.0e}: FAILED {str(err)[:120]}")
            continue
        spent += time.perf_counter() - began
        repeats = budget.repeats_for(first)
        extra, _ = timed_runs(lambda: contender.solve(tol, tol * problem.atol_ratio), repeats - 1)
        spent += sum(extra)
        point = Point(tol, "ok", [first, *extra], problem.errors(signals))
        times.append(point.time)
        curve.points.append(point)
        log(f"  {contender.name:12s} tol {tol:.0e}: {point.time * 1e3:9.1f} ms (n={point.runs})  "
            f"error {point.errors['error']:.2e}")
    return curve


def run_problem(problem: Problem, tolerances, budget: Budget, log) -> ProblemRun:
    began = time.perf_counter()
    contenders, unavailable = contenders_for(problem)
    for name, why in unavailable.items():
        log(f"  {name}: unavailable ({why})")
    curves = [sweep(c, problem, tolerances, budget, log) for c in contenders]
    return ProblemRun(problem, curves, unavailable, time.perf_counter() - began)


def _interpolated_log_time(curve: Curve, log_error: float) -> float | None:
    """log10 time at `log_error` by piecewise-linear interpolation of the curve's points
    (ordered by error); None outside the range the curve covers."""
    pts = sorted((math.log10(p.errors["error"]), math.log10(p.time)) for p in curve.ok())
    if len(pts) < 2:
        return None
    e, t = np.array([p[0] for p in pts]), np.array([p[1] for p in pts])
    if not e[0] <= log_error <= e[-1]:
        return None
    # the error need not be monotone in the tolerance: use the lower envelope of time per error
    best = None
    for i in range(len(e) - 1):
        lo, hi = e[i], e[i + 1]
        if lo <= log_error <= hi:
            value = t[i] if hi == lo else t[i] + (t[i + 1] - t[i]) * (log_error - lo) / (hi - lo)
            best = value if best is None else min(best, value)
    return best


def speedups(run: ProblemRun, errors_per_decade: int = 1) -> list[dict]:
    """At each decade of error that a dyadc curve and at least one scipy curve both reach:
    the time of each, and dyadc's speed-up over the fastest scipy method there."""
    rows = []
    dyadc = [c for c in run.curves if c.contender.startswith("dyadc")]
    scipy = [c for c in run.curves if c.contender.startswith("scipy")]
    all_errors = [p.errors["error"] for c in run.curves for p in c.ok()]
    if not all_errors:
        return rows
    lo, hi = math.floor(math.log10(min(all_errors))), math.ceil(math.log10(max(all_errors)))
    for log_error in np.arange(hi, lo - 1, -1.0 / errors_per_decade):
        scipy_times = {c.contender: _interpolated_log_time(c, log_error) for c in scipy}
        scipy_times = {k: v for k, v in scipy_times.items() if v is not None}
        if not scipy_times:
            continue
        best_name = min(scipy_times, key=scipy_times.get)
        for curve in dyadc:
            t = _interpolated_log_time(curve, log_error)
            if t is None:
                continue
            rows.append({"error": 10.0 ** log_error, "contender": curve.contender, "time": 10.0 ** t,
                         "best_scipy": best_name, "scipy_time": 10.0 ** scipy_times[best_name],
                         "speedup": 10.0 ** (scipy_times[best_name] - t)})
    return rows
