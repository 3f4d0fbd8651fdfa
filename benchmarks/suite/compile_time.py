"""Compile-time measurements in fresh processes: the excavator per stage, and the N-link chain."""
from __future__ import annotations

import json
import math
import statistics
import subprocess
import sys
from pathlib import Path

import numpy as np

SCRIPT = Path(__file__).resolve().parent / "compile_stages.py"
STAGES = ["parse", "flatten", "structure", "lower", "simulate"]
EXCAVATOR = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"


def _run(args: list[str], timeout: float) -> tuple[list[dict], str]:
    """Run compile_stages.py; the JSON lines it printed before finishing or timing out, and why
    it stopped early ("" if it finished)."""
    try:
        done = subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True,
                              timeout=timeout)
        stdout, problem = done.stdout, "" if done.returncode == 0 else done.stderr.strip()[-600:]
    except subprocess.TimeoutExpired as err:
        stdout = err.stdout.decode() if isinstance(err.stdout, bytes) else (err.stdout or "")
        problem = f"stopped after the {timeout:.0f} s time limit"
    rows = [json.loads(line) for line in stdout.splitlines() if line.startswith("{")]
    return rows, problem


def excavator_stages(repeats: int, log) -> dict:
    """Median over `repeats` cold processes of every stage time."""
    rows, problems = [], []
    for i in range(repeats):
        got, problem = _run(["model", EXCAVATOR, "12"], timeout=600)
        rows.extend(got)
        if problem:
            problems.append(problem)
        if got:
            log(f"  excavator cold compile #{i + 1}: " + ", ".join(
                f"{k} {got[0][k]:.2f}" for k in ["import", *STAGES, "c_build", "process"] if k in got[0]))
    keys = ["import", *STAGES, "c_build", "process"]
    median = {k: statistics.median(r[k] for r in rows) for k in keys if rows and all(k in r for r in rows)}
    return {"median": median, "runs": len(rows), "problems": problems,
            "sizes": {k: rows[0][k] for k in ("equations", "states", "algebraics", "steps")} if rows else {}}


def growth_exponent(n: list[float], t: list[float]) -> float:
    """Slope of the least-squares line through (log N, log t)."""
    return float(np.polyfit(np.log(n), np.log(t), 1)[0])


def chain_scaling(sizes: list[int], budget_s: float, log) -> dict:
    rows, problem = _run(["chain", str(budget_s), *map(str, sizes)], timeout=budget_s * 2.5 + 120)
    measured = [r for r in rows if "skipped" not in r]
    for r in measured:
        r["total"] = sum(r[s] for s in STAGES)
        log(f"  chain N={r['n']:4d}: " + ", ".join(f"{s} {r[s]:.2f}" for s in STAGES) + f", total {r['total']:.2f} s")
    done = {r["n"] for r in rows}
    skipped = [{"n": r["n"], "why": r["skipped"]} for r in rows if "skipped" in r]
    skipped += [{"n": n, "why": problem or "not reached"} for n in sizes if n not in done]
    fit_rows = [r for r in measured if r["n"] >= 4]
    fit = {}
    if len(fit_rows) >= 2:
        for stage in STAGES + ["total"]:
            values = [max(r[stage], 1e-6) for r in fit_rows]
            fit[stage] = growth_exponent([r["n"] for r in fit_rows], values)
    return {"rows": measured, "skipped": skipped, "fit": fit, "fit_from": 4, "problem": problem}


def predicted_total(fit: dict, rows: list[dict], n: int) -> float:
    last = rows[-1]
    return last["total"] * math.pow(n / last["n"], fit["total"])
