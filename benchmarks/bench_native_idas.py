"""The native IDAS driver against CasADi's IDAS (issue 32 item 2) -> docs/numerics.md.

    .venv/bin/python benchmarks/bench_native_idas.py [--repeats 7] [--doc docs/numerics.md]

The excavator (bench_floor.py's run: 12 s, rtol = atol = 1e-6, 1201 points), compiled
once, run side by side in this process (CPU time, medians, the three ways interleaved): CasADi's
IDAS on CasADi's VM, CasADi's IDAS on the model's C library, and the native driver on the same C
library; and the issue's yardstick, one bare CasADi IDAS call on the model's own DAE on the VM
(bench_floor.py's floor: one casadi.integrator per segment, built per call, x and z on the
grid, no outputs). The switching pendulum (bench_switching.py's run) on both integrators in C shows what
keeping IDAS between calls and finding the switches by root gives. The table replaces the text
between the markers in the doc.
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from compiler import api, runtime  # noqa: E402
from compiler.cache.c_code import compile_c, on_vm  # noqa: E402
from compiler.runtime.initialization import consistent_initialization  # noqa: E402
from compiler.runtime.native import library, make_integrator  # noqa: E402
import bench_floor  # noqa: E402

BEGIN, END = "<!-- native idas: begin -->", "<!-- native idas: end -->"
EXCAVATOR = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"
THETA0, L, G, STOP, RTOL, POINTS = 2.3, 0.8, 9.81, 20.0, 1e-8, 2001   # bench_switching.py's run


def cpu_runs(runs: dict, repeats: int) -> dict:
    """{label: (median CPU seconds, last result)}, the runs interleaved `repeats` times."""
    times = {label: [] for label in runs}
    results = {}
    for _ in range(repeats):
        for label, run in runs.items():
            began = time.process_time()
            results[label] = run()
            times[label].append(time.process_time() - began)
    return {label: (float(np.median(times[label])), results[label]) for label in runs}


def excavator(repeats: int) -> dict:
    """bench_floor.py's run: 12 s, rtol = atol = 1e-6, 1201 points."""
    compilation = api.compile(EXCAVATOR)
    vm, c = on_vm(compilation.model), compile_c(compilation.model)
    stop, points = bench_floor.STOP, 1201
    settings = dict(rtol=bench_floor.RTOL, atol=bench_floor.ATOL, points=points)
    # CasADi's IDAS by name: since paths32 runtime.simulate's default is the native driver on C
    return cpu_runs({"CasADi IDAS, VM": lambda: runtime.simulate(vm, stop, integrator="casadi", **settings),
                     "bare CasADi IDAS call, VM (bench_floor.py)": bare_call(vm, stop, points),
                     "CasADi IDAS, C": lambda: runtime.simulate(c, stop, integrator="casadi", **settings),
                     "native IDAS, C": lambda: runtime.simulate(c, stop, integrator=make_integrator,
                                                                **settings)}, repeats)


class BareResult:
    """What table() reads of a run, for the bare call."""
    def __init__(self, steps: int, calls: int):
        self.stats = {"steps": steps, "segments": calls, "state_switches": []}
        self.events = []


def bare_call(model, stop: float, points: int, rtol: float = bench_floor.RTOL):
    """bench_floor.py's floor: one bare CasADi IDAS call per segment on the model's DAE (atol =
    rtol); the result's stats hold IDAS's counters summed over the calls (CasADi's names)."""
    p = model.parameter_vector(None)
    point = consistent_initialization(model, p, 0.0)
    grid = np.linspace(0.0, stop, points)

    def run():
        counters: dict = {}
        steps = bench_floor.floor_run(model, bench_floor.floor_dae(model), p, point, grid, rtol, rtol,
                                      counters)[3]
        result = BareResult(steps, len(bench_floor.segment_ends(model, p)))
        result.stats["idas"] = counters
        return result
    return run


def pendulum(repeats: int) -> dict:
    compilation = api.compile("Hard.PendulumA01", lib_dirs=(str(ROOT / "tests" / "models"),))
    c = compile_c(compilation.model)
    settings = dict(rtol=RTOL, atol=RTOL, points=POINTS,
                    params={"y0": -L * np.cos(THETA0), "L": L, "g": G})
    return cpu_runs({"CasADi IDAS, C": lambda: runtime.simulate(c, STOP, integrator="casadi", **settings),
                     "native IDAS, C": lambda: runtime.simulate(c, STOP, integrator=make_integrator,
                                                                **settings)}, repeats)


def table(title: str, measured: dict, reference: str) -> list[str]:
    lines = [title, "", "| run | CPU | x " + reference + " | IDAS steps | IDAS calls | events + switches |",
             "|---|---|---|---|---|---|"]
    base = measured[reference][0]
    for label, (seconds, result) in measured.items():
        s = result.stats
        lines.append(f"| {label} | {seconds * 1e3:.1f} ms | {seconds / base:.2f} | {s['steps']} | "
                     f"{s['segments']} | {len(result.events) + len(s['state_switches'])} |")
    return lines + [""]


def write(doc: Path, lines: list[str]) -> None:
    text = doc.read_text(encoding="utf-8")
    head, rest = text.split(BEGIN)
    tail = rest.split(END)[1]
    doc.write_text(head + BEGIN + "\n\n" + "\n".join(lines) + "\n" + END + tail, encoding="utf-8")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--doc", type=Path, default=None)
    arguments = parser.parse_args()
    if library.driver_library()[0] is None:
        sys.exit(library.driver_library()[1])
    stamp = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    load = os.getloadavg()[0]
    lines = [f"Measured {stamp} by benchmarks/bench_native_idas.py (SUNDIALS "
             f"{library.sundials_version()} native, CasADi's own IDAS otherwise), CPU medians of "
             f"{arguments.repeats} interleaved runs in one process, on a 2-core machine shared with "
             f"other work (load average {load:.1f} at the start):", ""]
    lines += table("The excavator (12 s, rtol = atol = 1e-6, 1201 points, every output computed):",
                   excavator(arguments.repeats), "CasADi IDAS, VM")
    lines += table(f"The switching pendulum (A01 at {THETA0} rad, {STOP:g} s, rtol = atol = {RTOL:g}, "
                   f"{POINTS} points):", pendulum(arguments.repeats), "CasADi IDAS, C")
    print("\n".join(lines))
    if arguments.doc is not None:
        write(arguments.doc, lines)
