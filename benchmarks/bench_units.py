"""What the unit check adds to the excavator's uncached compile (issue 26, item 9): compiles in
fresh processes, alternating `--units off` and `--units error` so that both see the same machine
load, and the check's own time in one process. Short: about a minute.

    .venv/bin/python benchmarks/bench_units.py [--repeats 7]
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXCAVATOR = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"

COMPILE = r'''
import json, sys, time
from compiler.pipeline import compile_spec, _library
from compiler.units.mode import units_mode
began, cpu = time.perf_counter(), time.process_time()
with units_mode(sys.argv[1]):
    compile_spec(sys.argv[2], library=_library(()))
print(json.dumps({"seconds": time.perf_counter() - began, "cpu": time.process_time() - cpu}))
'''

CHECK_ONLY = r'''
import json, sys, time
from compiler.model.instantiate import instantiate
from compiler.model.model_spec import resolve_model
from compiler.pipeline import _library
from compiler.units.check import check_units
library = _library(())
model = instantiate(resolve_model(sys.argv[1], library), library)
times = []
for _ in range(int(sys.argv[2])):
    began = time.process_time()
    findings = check_units(model)
    times.append(time.process_time() - began)
print(json.dumps({"cpu": sorted(times)[len(times) // 2], "findings": len(findings)}))
'''


def run(script: str, *args: str) -> dict:
    out = subprocess.run([sys.executable, "-c", script, *args], capture_output=True, text=True,
                         check=True, cwd=ROOT, env={**os.environ, "DYADC_CACHE_DIR": "off"})
    return json.loads(out.stdout)


def measure(repeats: int) -> dict:
    """Medians of `repeats` uncached compiles per mode, alternating, and the check's own time."""
    runs: dict[str, list[dict]] = {"off": [], "error": []}
    for _ in range(repeats):
        for mode in ("off", "error"):
            runs[mode].append(run(COMPILE, mode, EXCAVATOR))
    return {"repeats": repeats, "runs": runs, "check": run(CHECK_ONLY, EXCAVATOR, str(repeats))}


def render(result: dict) -> str:
    """A markdown section for docs/benchmarks.md (make bench) or the terminal."""
    runs, repeats = result["runs"], result["repeats"]
    lines = ["## Unit check cost (issue 26, item 9)", "",
             f"Excavator uncached compile, median of {repeats} fresh processes per mode, alternating "
             f"(CPU time of the process; wall time in brackets, which other load moves). Target: the "
             f"check adds under 10 %.", "", "| mode | CPU | wall | each run (CPU) |", "| --- | --- | --- | --- |"]
    median = {}
    for mode in ("off", "error"):
        cpu = statistics.median(r["cpu"] for r in runs[mode])
        wall = statistics.median(r["seconds"] for r in runs[mode])
        median[mode] = cpu
        each = " ".join(f"{r['cpu']:.3f}" for r in runs[mode])
        lines.append(f"| `--units {mode}` | {cpu:.3f} s | {wall:.3f} s | {each} |")
    off, on = median["off"], median["error"]
    check = result["check"]
    met = "met" if on - off < 0.10 * off else "NOT met"
    lines += ["", f"Difference {on - off:+.3f} s CPU ({(on - off) / off * 100:+.1f} %): {met}. "
              f"`check_units` alone: {check['cpu'] * 1e3:.1f} ms CPU ({check['cpu'] / off * 100:.1f} % of "
              f"the compile), {check['findings']} findings.", ""]
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    print(render(measure(args.repeats)))


if __name__ == "__main__":
    main()
