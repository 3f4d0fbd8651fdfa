"""Time of every structure pass on a planar chain of N links (library World, Revolute, BodyShape).

Passes, in pipeline order: alias (alias and constant elimination), rank (the derivative-rank check
and building the integer-indexed system), index reduction (Pantelides and the symbolic
differentiation it asks for), dummy derivatives (state selection with numeric pivoting),
causalize (matching, BLT, tearing), assemble (assignments, pruning, the initialization problem)
and lower (sympy -> CasADi functions). Each pass is timed on its own, on the output of the
previous one; the median over a few repeats is printed with the growth exponent between
successive sizes (t ~ N^k: k = 1 is linear).

Usage: python benchmarks/bench_structure.py [--budget SECONDS] [N ...]    (default 10 100 1000, 900 s)

A size whose predicted time (each pass extrapolated with its growth exponent between the last two
sizes measured) exceeds the budget is skipped with its prediction, not run.
"""
from __future__ import annotations

import math
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

# The rank pass makes hundreds of small lstsq calls: with OpenBLAS's spinning worker threads on
# a loaded 2-core machine they took 20 s instead of 0.4 s (N = 30). One BLAS thread, set before
# numpy is imported.
for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import sympy  # noqa: E402

from compiler.model.flatten import flatten_model  # noqa: E402
from compiler.lower.to_casadi import lower  # noqa: E402
from compiler.structure import reduce as structure  # noqa: E402
from compiler.structure.alias import eliminate_aliases  # noqa: E402
from compiler.structure.derivative_rank import remove_derivative_dependencies  # noqa: E402
from compiler.structure.index_reduction import reduce_index  # noqa: E402
from compiler.structure.indexed import build_indexed  # noqa: E402
from suite.chain_model import write_chain  # noqa: E402

PASSES = ["alias", "rank", "index reduction", "dummy derivatives", "causalize", "assemble", "lower"]


def timed(function, *args, **kwargs):
    began = time.perf_counter()
    value = function(*args, **kwargs)
    return value, time.perf_counter() - began


def pass_times(flat) -> dict[str, float]:
    """One run of the structure stage and lowering, pass by pass (mirrors structure.analyse)."""
    times = {}
    alias, times["alias"] = timed(eliminate_aliases, flat)

    began = time.perf_counter()
    residuals = [e.residual for e in alias.equations]
    parameter_values = {sympy.Symbol(p.name): p.value for p in flat.parameters if p.value is not None}
    residuals, rank_report = remove_derivative_dependencies(
        residuals, {sympy.Symbol(d) for d in alias.derivatives}, parameter_values)
    derivatives = structure._occurring_derivatives(alias.derivatives, residuals)
    system = build_indexed(alias.kept, derivatives, residuals, [e.origin for e in alias.equations])
    structure._check_square(flat, system)
    times["rank"] = time.perf_counter() - began

    (reduced_system, index_report), times["index reduction"] = timed(reduce_index, system)
    analysis = structure.Analysis(alias, reduced_system, index_report, structure._priorities(flat, alias), rank_report)

    report = structure.StructureReport()
    reduced, total = timed(structure.reduce, flat, point=flat.initial_values(), report=report, analysis=analysis)
    times["dummy derivatives"] = report.timings["dummy derivatives"]
    times["causalize"] = report.timings["causalize"]
    # reduce() times its own passes; what it does not time is the assembly
    times["assemble"] = total - sum(report.timings.values())
    _, times["lower"] = timed(lower, reduced)
    times["_states"] = len(reduced.states)
    times["_equations"] = len(flat.equations)
    return times


def bench(n: int, folder: Path, repeats: int) -> tuple[dict[str, float], dict]:
    flat, flatten_seconds = timed(flatten_model, write_chain(n, folder))
    runs = [pass_times(flat) for _ in range(repeats)]
    medians = {p: statistics.median(r[p] for r in runs) for p in PASSES}
    info = {"flatten": flatten_seconds, "equations": runs[0]["_equations"], "states": runs[0]["_states"]}
    return medians, info


def predicted_seconds(rows: list[tuple[int, dict[str, float]]], n: int) -> float | None:
    if len(rows) < 2:
        return None
    (n1, t1), (n2, t2) = rows[-2], rows[-1]
    total = 0.0
    for p in PASSES:
        k = max(1.0, math.log(t2[p] / t1[p]) / math.log(n2 / n1)) if t1[p] > 0 and t2[p] > 0 else 1.0
        total += t2[p] * (n / n2) ** k
    return total


def main(argv: list[str]) -> None:
    budget = 900.0
    if "--budget" in argv:
        at = argv.index("--budget")
        budget = float(argv[at + 1])
        argv = argv[:at] + argv[at + 2:]
    sizes = [int(a) for a in argv] or [10, 100, 1000]
    rows = []
    with tempfile.TemporaryDirectory(prefix="dyadc-bench-structure-") as tmp:
        bench(2, Path(tmp), 1)                      # warm-up: parser tables, imports, caches
        for n in sizes:
            repeats = 5 if n <= 10 else 3 if n <= 100 else 1
            prediction = predicted_seconds(rows, n)
            if prediction is not None and prediction > budget:
                print(f"N={n:5d}  skipped: predicted {prediction:.0f} s for one run, beyond the {budget:.0f} s "
                      "budget (--budget to change)", flush=True)
                continue
            if prediction is not None and prediction * repeats > budget:
                repeats = 1
            medians, info = bench(n, Path(tmp), repeats)
            rows.append((n, medians))
            print(f"N={n:5d}  ({info['equations']} flat equations, {info['states']} states, "
                  f"flatten {info['flatten']:.2f} s, median of {repeats})", flush=True)
            for p in PASSES:
                print(f"    {p:18s} {medians[p] * 1e3:11.1f} ms")
            print(f"    {'total':18s} {sum(medians.values()) * 1e3:11.1f} ms", flush=True)
    if len(rows) > 1:
        print("\ngrowth exponents k (t ~ N^k) between successive sizes:")
        header = "".join(f"{f'{a}->{b}':>12s}" for (a, _), (b, _) in zip(rows, rows[1:]))
        print(f"    {'pass':18s}{header}")
        for p in PASSES + ["total"]:
            cells = []
            for (n1, t1), (n2, t2) in zip(rows, rows[1:]):
                a = sum(t1.values()) if p == "total" else t1[p]
                b = sum(t2.values()) if p == "total" else t2[p]
                cells.append(f"{math.log(b / a) / math.log(n2 / n1):12.2f}" if a > 0 and b > 0 else f"{'-':>12s}")
            print(f"    {p:18s}{''.join(cells)}")


if __name__ == "__main__":
    main(sys.argv[1:])
