"""The Test Set's transistor amplifier over a sweep of tolerances, on the native IDAS driver and on
CasADi's IDAS -> docs/numerics.md (issue 32: the native path failed at some tolerances near 1e-10).

    .venv/bin/python benchmarks/bench_transistor_sweep.py [--count 30] [--doc docs/numerics.md]

tests/structure/models' StructureModels.TransistorAmplifier over 0.2 s, rtol = atol, 2001 output
points, at `count` log-spaced tolerances from 1e-6 to 1e-11 and the ones that failed before. Each
tolerance runs on both paths; a row says whether each ran, the largest difference between the
paths over every output point and signal (relative to the signal's largest magnitude) and at
t = 0.2, and both paths' distance from the Test Set's reference at t = 0.2. The table replaces
the block between its markers in the doc.
"""
from __future__ import annotations

import argparse
import sys
import time
import warnings
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from compiler import api  # noqa: E402
from compiler.errors import SimulationError  # noqa: E402
from compiler.runtime.native import NativeIdasWarning, library  # noqa: E402
from suite.doc_blocks import write_block  # noqa: E402

BEGIN, END = "<!-- transistor amplifier sweep: begin -->", "<!-- transistor amplifier sweep: end -->"
MODELS = ROOT / "tests" / "structure" / "models"
STOP, POINTS = 0.2, 2001
# the tolerances that failed on the native path before the fix (docs/numerics.md)
FAILED_BEFORE = (1.1e-10, 5e-11, 8e-11, 9e-11, 1e-10, 1.25e-10, 2e-10)
SIGNALS = [f"y{i}" for i in range(1, 9)]
# Hairer & Wanner's transistor amplifier at t = 0.2 (Test Set for IVP Solvers, `transamp`), as in
# tests/structure/test_models.py
REFERENCE = np.array([
    -0.5562145012262709e-02, 0.3006522471903042e+01, 0.2849958788608128e+01, 0.2926422536206241e+01,
    0.2704617865010554e+01, 0.2761837778393145e+01, 0.4770927631616772e+01, 0.1236995868091548e+01])


def tolerances(count: int) -> list[float]:
    sweep = {float(f"{v:.3g}") for v in np.logspace(-6, -11, count)}
    return sorted(sweep | set(FAILED_BEFORE), reverse=True)


def one_run(compilation, tol: float, integrator: str) -> dict:
    began = time.process_time()
    try:
        result = api.simulate_compiled(compilation, STOP, rtol=tol, atol=tol, points=POINTS,
                                       integrator=integrator)
    except SimulationError as err:
        return {"ran": False, "why": str(err).splitlines()[0][:160]}
    values = np.array([result[name] for name in SIGNALS])
    return {"ran": True, "time": time.process_time() - began, "values": values,
            "integrator": result.stats.get("integrator"), "steps": result.stats.get("steps"),
            "switches": len(result.stats.get("state_switches", ())),
            "reference_error": float(np.max(np.abs(values[:, -1] - REFERENCE)))}


def measure(count: int, log=print) -> dict:
    compilation = api.compile("StructureModels.TransistorAmplifier", lib_dirs=(str(MODELS),))
    rows = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NativeIdasWarning)
        for tol in tolerances(count):
            native, casadi = one_run(compilation, tol, "native"), one_run(compilation, tol, "casadi")
            row = {"tol": tol, "native": native, "casadi": casadi}
            if native["ran"] and casadi["ran"]:
                scale = np.max(np.abs(casadi["values"]), axis=1, keepdims=True)
                row["difference"] = float(np.max(np.abs(native["values"] - casadi["values"]) / scale))
                row["final"] = float(np.max(np.abs(native["values"][:, -1] - casadi["values"][:, -1])))
            rows.append(row)
            log(summary(row))
    return {"rows": rows, "stamp": datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "sundials": library.sundials_version()}


def summary(row: dict) -> str:
    native, casadi = row["native"], row["casadi"]
    return (f"rtol {row['tol']:.3g}: native {'ran' if native['ran'] else 'FAILED ' + native['why']}, "
            f"CasADi {'ran' if casadi['ran'] else 'FAILED ' + casadi['why']}"
            + (f", paths differ by {row['difference']:.3g} (at t = {STOP}: {row['final']:.3g}); reference errors "
               f"{native['reference_error']:.3g} native, {casadi['reference_error']:.3g} CasADi"
               if "difference" in row else ""))


def cell(run: dict) -> str:
    if not run["ran"]:
        return "fails"
    return f"{run['steps']} steps, {run['switches']} switches, {run['reference_error']:.1e}"


def agrees(row: dict) -> bool:
    """The paths' difference at t = 0.2 within each path's own distance from the reference."""
    return "final" in row and row["final"] <= max(row["native"]["reference_error"],
                                                  row["casadi"]["reference_error"])


def render(data: dict) -> list[str]:
    rows = data["rows"]
    ran = sum(r["native"]["ran"] for r in rows)
    lines = [BEGIN, "", f"Measured {data['stamp']} by benchmarks/bench_transistor_sweep.py (native driver: "
             f"SUNDIALS {data['sundials']}): StructureModels.TransistorAmplifier, {STOP} s, rtol = atol, "
             f"{POINTS} points. Native runs: {ran} of {len(rows)}; CasADi's IDAS: "
             f"{sum(r['casadi']['ran'] for r in rows)} of {len(rows)}; the paths' difference at t = {STOP} "
             f"is within the larger of their distances from the Test Set's reference at "
             f"{sum(agrees(r) for r in rows)} of {len(rows)} tolerances. Each path's cell: IDAS steps, "
             f"state-set switches, largest distance from the reference at t = {STOP}. \"differ\": the largest "
             f"difference between the paths at any output point, relative to the signal's largest "
             f"magnitude, and at t = {STOP}.", "",
             "| rtol = atol | native | CasADi's IDAS | differ (any point, relative) | differ at t = 0.2 |",
             "|---|---|---|---|---|"]
    for row in rows:
        differ = f"{row['difference']:.2g} | {row['final']:.2g}" if "difference" in row else "- | -"
        lines.append(f"| {row['tol']:.3g} | {cell(row['native'])} | {cell(row['casadi'])} | {differ} |")
    return lines + ["", END]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=30, help="log-spaced tolerances from 1e-6 to 1e-11")
    parser.add_argument("--doc", type=Path, default=ROOT / "docs" / "numerics.md")
    arguments = parser.parse_args()
    data = measure(arguments.count)
    write_block(arguments.doc, "\n".join(render(data)), BEGIN, END)
    print(f"written to {arguments.doc}")


if __name__ == "__main__":
    main()
