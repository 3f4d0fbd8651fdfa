"""dyadc against the hand-written scipy Radau excavator at matched bucket-tip error (issue 15 item 2).

The scipy model (benchmarks/contenders/scipy_excavator.py) runs at rtol = atol = 1e-6; dyadc runs
at the loosest rtol (atol = rtol, the work-precision settings) of RTOLS whose tip error is no worse.
Tip error: the largest distance over the 1201-point grid between the bucket tip (bucket.frame_b)
and the reference's (problems.Excavator.reference), in metres. Times are CPU seconds of this
process around each solve (the machine is shared: wall time would measure the other work), medians
of `repeats` interleaved solves after a warm-up each, all in this one run.
"""
from __future__ import annotations

import statistics
import time

import numpy as np

from suite.contenders import DyadcContender, Failed, ScipyContender
from suite.problems import Problem

SCIPY_METHOD, SCIPY_RTOL = "Radau", 1e-6
RTOLS = (1e-5, 3e-6, 1e-6, 3e-7, 1e-7, 3e-8, 1e-8)
TIP = ("bucket.frame_b.x", "bucket.frame_b.y")


def tip_error(problem: Problem, signals: dict) -> float:
    reference = problem.reference
    return float(np.max(np.hypot(*(np.asarray(signals[n]) - reference[n] for n in TIP))))


def cpu_solve(contender, rtol: float, atol_ratio: float) -> tuple[float, dict]:
    """CPU seconds of this process around one solve, and the signals."""
    began = time.process_time()
    _, signals = contender.solve(rtol, rtol * atol_ratio)
    return time.process_time() - began, signals


def loosest_matching(problem: Problem, contender, target: float, rtols=RTOLS) -> dict:
    """The loosest of `rtols` (tried loosest first) whose tip error is no worse than `target`:
    {"contender", "rtol", "tip", "tried": [(rtol, tip or None)], "notes"}; "rtol" is None where
    none reaches it."""
    tried, notes = [], []
    for rtol in rtols:
        try:
            _, signals = cpu_solve(contender, rtol, problem.atol_ratio)
        except Failed as err:
            tried.append((rtol, None))
            notes.append(f"{contender.name} failed at rtol {rtol:.0e}: {err}")
            continue
        tip = tip_error(problem, signals)
        tried.append((rtol, tip))
        if tip <= target:
            return {"contender": contender, "rtol": rtol, "tip": tip, "tried": tried, "notes": notes}
    notes.append(f"{contender.name}: no rtol down to {rtols[-1]:.0e} reaches the tip error {target:.2e} m "
                 f"({', '.join(f'{r:.0e}: {t:.2e}' for r, t in tried if t is not None)})")
    return {"contender": contender, "rtol": None, "tip": None, "tried": tried, "notes": notes}


def matched_tip_error(problem: Problem, repeats: int, log) -> dict:
    """{"scipy": {...}, "dyadc": [{contender, rtol, tip, time, speedup}], "notes": [...]}"""
    ratio = problem.atol_ratio
    scipy = ScipyContender(problem, SCIPY_METHOD)
    _, signals = cpu_solve(scipy, SCIPY_RTOL, ratio)                        # warm-up
    target = tip_error(problem, signals)
    log(f"  scipy {SCIPY_METHOD} rtol {SCIPY_RTOL:.0e}: tip error {target:.2e} m")
    chosen, notes = [], []
    for codegen in ("vm", "c"):
        try:
            contender = DyadcContender(problem, codegen)
        except Failed as err:
            notes.append(f"dyadc ({codegen.upper()}) unavailable: {err}")
            continue
        found = loosest_matching(problem, contender, target)
        notes += found["notes"]
        if found["rtol"] is not None:
            chosen.append(found)
            log(f"  {contender.name}: rtol {found['rtol']:.0e} tip error {found['tip']:.2e} m")
    times = {id(c): [] for c in chosen}
    scipy_times = []
    for _ in range(repeats):                                             # interleaved
        scipy_times.append(cpu_solve(scipy, SCIPY_RTOL, ratio)[0])
        for c in chosen:
            times[id(c)].append(cpu_solve(c["contender"], c["rtol"], ratio)[0])
    scipy_time = statistics.median(scipy_times)
    rows = [{"contender": c["contender"].name, "rtol": c["rtol"], "tip": c["tip"],
             "time": statistics.median(times[id(c)]), "runs": repeats,
             "speedup": scipy_time / statistics.median(times[id(c)]),
             "tried": [(r, t) for r, t in c["tried"]]} for c in chosen]
    for r in rows:
        log(f"  {r['contender']}: {r['time'] * 1e3:.1f} ms CPU vs scipy {scipy_time * 1e3:.0f} ms: "
            f"{r['speedup']:.1f}x")
    return {"scipy": {"method": SCIPY_METHOD, "rtol": SCIPY_RTOL, "tip": target, "time": scipy_time,
                      "runs": repeats}, "dyadc": rows, "notes": notes}


def report_lines(data: dict) -> list[str]:
    s = data["scipy"]
    lines = ["### Matched tip error: dyadc vs the hand-written scipy Radau model", "",
             f"The scipy model at rtol = atol = {s['rtol']:.0e} reaches a bucket-tip error of {s['tip']:.2e} m "
             f"(max over the 1201-point grid of the distance to the reference tip). dyadc at the loosest "
             f"rtol of {', '.join(f'{r:.0e}' for r in RTOLS)} whose tip error is no worse; CPU time of each "
             f"solve, medians of {s['runs']} interleaved solves in one run:", "",
             "| contender | rtol | tip error [m] | median CPU time | speed-up vs scipy Radau |",
             "|---|---|---|---|---|",
             f"| scipy {s['method']} | {s['rtol']:.0e} | {s['tip']:.2e} | {s['time'] * 1e3:.0f} ms | 1 |"]
    for r in data["dyadc"]:
        lines.append(f"| {r['contender']} | {r['rtol']:.0e} | {r['tip']:.2e} | {r['time'] * 1e3:.1f} ms | "
                     f"**{r['speedup']:.1f}x** |")
    for r in data["dyadc"]:
        lines.append("")
        lines.append(f"{r['contender']} tip errors tried: "
                     + ", ".join(f"rtol {rt:.0e}: {t:.2e} m" if t is not None else f"rtol {rt:.0e}: failed"
                                 for rt, t in r["tried"]) + ".")
    lines += [f"- {note}" for note in data["notes"]]
    return lines + [""]
