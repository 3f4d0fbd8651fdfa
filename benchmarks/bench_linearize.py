"""Linearizing the excavator from the compilation cache (issue 29 target: under 50 ms).

    .venv/bin/python benchmarks/bench_linearize.py [--repeats N] [--doc docs/analysis.md]

Each sample is one `compiler.api.linearize` call in this process with the cache warm: the
compiled model read from the cache (a new model object, so nothing derived from an earlier call
is reused), the consistent initial point, the CasADi Jacobian of [der(x); alg; y] built and
evaluated, the algebraic unknowns eliminated. CPU time (process_time), median of the samples.
The table replaces the text between the markers in the doc.
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from suite.doc_blocks import write_block  # noqa: E402

EXCAVATOR = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"
TARGET_S = 0.050
BEGIN, END = "<!-- bench_linearize: begin -->", "<!-- bench_linearize: end -->"


def measure(repeats: int) -> dict:
    from compiler import api
    from compiler.pipeline import compile_or_load
    compile_or_load(EXCAVATOR)                       # the cache holds the excavator from here on
    api.linearize(EXCAVATOR, outputs=["boom_joint.phi"])     # imports and first-use costs
    samples, walls = [], []
    for _ in range(repeats):
        began_cpu, began_wall = time.process_time(), time.perf_counter()
        system = api.linearize(EXCAVATOR, outputs=["boom_joint.phi"])
        samples.append(time.process_time() - began_cpu)
        walls.append(time.perf_counter() - began_wall)
    return {"cpu": statistics.median(samples), "wall": statistics.median(walls), "repeats": repeats,
            "states": len(system.states)}


def render(found: dict) -> str:
    met = "yes" if found["cpu"] < TARGET_S else "no"
    return "\n".join([
        BEGIN,
        "| measurement | value |", "|---|---|",
        f"| excavator from the cache, `api.linearize` ({found['states']} states), CPU median of "
        f"{found['repeats']} | {found['cpu'] * 1e3:.1f} ms (wall {found['wall'] * 1e3:.1f} ms) |",
        f"| target: under {TARGET_S * 1e3:.0f} ms | {met} |",
        END])


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=15)
    parser.add_argument("--doc", default=str(ROOT / "docs" / "analysis.md"))
    args = parser.parse_args(argv)
    table = render(measure(args.repeats))
    write_block(Path(args.doc), table, BEGIN, END, heading="Speed")
    print(table)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
