"""Cold start with an output file (issue 28): a cached `dyadc simulate` of the excavator writing all
631 signals at 1201 points to CSV, in a new process, against `python -c "import casadi, numpy"`
measured side by side (target: within OUTPUT_RATIO times that import).

Three kinds of new processes, interleaved, `--repeat` of each after a warm-up that fills the
compilation cache and writes Python's bytecode (as bench_coldstart.py runs them, on a snapshot of
the sources):

  import   python -c "import casadi, numpy"
  bare     dyadc simulate EXCAVATOR --stop 12 --points 1201            (final values printed)
  csv      the same with --output out.csv

Medians of wall time (what the user waits for, as the issue measured it) and CPU time (user + sys
of the child: what dyadc costs on a loaded machine); the ratios are of the medians.

    .venv/bin/python benchmarks/bench_output_start.py [--repeat 7] [--ref HEAD]
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import bench_coldstart
from bench_coldstart import EXCAVATOR, dyadc, environment, snapshot, timed_run

OUTPUT_RATIO = 3.0
KINDS = ("import", "bare", "csv")


def measure(repeat: int, stop: float = 12.0, points: int = 1201) -> dict[str, list[tuple[float, float]]]:
    """(wall s, CPU s) of each kind of process, `repeat` of each, interleaved."""
    run = ["simulate", EXCAVATOR, "--stop", str(stop), "--points", str(points)]
    samples: dict[str, list[tuple[float, float]]] = {kind: [] for kind in KINDS}
    with tempfile.TemporaryDirectory(prefix="dyadc-bench-output-") as scratch:
        env = environment(Path(scratch) / "cache", Path(scratch) / "bytecode")
        output = str(Path(scratch) / "out.csv")
        commands = {"import": [sys.executable, "-c", "import casadi, numpy"],
                    "bare": dyadc(*run), "csv": dyadc(*run, "--output", output)}
        for command in commands.values():           # cache filled, bytecode written
            timed_run(command, env)
        for _ in range(repeat):
            for kind, command in commands.items():
                samples[kind].append(timed_run(command, env))
    return samples


def medians(samples: dict[str, list[tuple[float, float]]]) -> dict[str, tuple[float, float]]:
    return {kind: (statistics.median(w for w, _ in runs), statistics.median(c for _, c in runs))
            for kind, runs in samples.items() if runs}


def render(samples: dict[str, list[tuple[float, float]]]) -> list[str]:
    """A markdown table: medians, each run, and the ratios to the import."""
    found = medians(samples)
    base_wall, base_cpu = found["import"]
    lines = ["| process | wall s | CPU s | wall / import | CPU / import | wall, each run |",
             "|---|---|---|---|---|---|"]
    labels = {"import": '`python -c "import casadi, numpy"`', "bare": "cached `dyadc simulate`, no output",
              "csv": "cached `dyadc simulate --output out.csv` (631 signals x 1201 points)"}
    for kind in KINDS:
        wall, cpu = found[kind]
        lines.append(f"| {labels[kind]} | {wall:.3f} | {cpu:.3f} | {wall / base_wall:.2f}x | "
                     f"{cpu / base_cpu:.2f}x | {' '.join(f'{w:.2f}' for w, _ in samples[kind])} |")
    return lines


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--ref", metavar="COMMIT", help="measure this commit instead of the work tree")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="dyadc-bench-sources-") as copy:
        bench_coldstart.SOURCES = snapshot(Path(copy), args.ref)
        used = subprocess.run([sys.executable, "-c", "import compiler; print(compiler.__file__)"],
                              cwd=bench_coldstart.SOURCES, capture_output=True, text=True, check=True).stdout
        if not Path(used.strip()).is_relative_to(bench_coldstart.SOURCES):
            raise SystemExit(f"the runs would import {used.strip()}, not the snapshot")
        samples = measure(args.repeat)
    print(f"medians of {args.repeat} new processes each, interleaved (load average "
          f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)\n")
    print("\n".join(render(samples)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
