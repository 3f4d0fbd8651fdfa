"""Runtime benchmark: lowering, C build, and IDAS run time on the CasADi VM vs compiled C.

Model: a chain of n masses on springs with dampers, spring forces as algebraic unknowns
(3n unknowns), 10 s, rtol 1e-8; "light" = cubic springs, "heavy" = smooth saturating laws with
roots, trig and exp (the excavator's kind of expressions). Run: `.venv/bin/python benchmarks/bench_runtime.py [n ...]`.
The C library is built into a fresh cache each time, so its build time is the uncached cost.
"""
from __future__ import annotations

import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from tests.runtime import runtime_systems as systems  # noqa: E402
from compiler import runtime  # noqa: E402
from compiler.cache.c_code import compile_c, on_vm
from compiler.lower import ccodegen
from compiler.lower.to_casadi import lower  # noqa: E402


def best_run(model, repeats: int = 3) -> tuple[float, runtime.Result]:
    best, result = float("inf"), None
    for _ in range(repeats):
        began = time.perf_counter()
        result = runtime.simulate(model, 10.0, rtol=1e-8, atol=1e-10, progress=False)
        best = min(best, time.perf_counter() - began)
    return best, result


def bench(n: int, heavy: bool) -> dict:
    began = time.perf_counter()
    reduced = systems.mass_chain(n, heavy=heavy)
    vm = on_vm(lower(reduced))      # asked for: an undecided model's first run would build C
    lower_time = time.perf_counter() - began
    row = {"model": "heavy" if heavy else "light", "n_unknowns": 3 * n, "lower_s": lower_time}
    row["vm_s"], vm_result = best_run(vm)
    row["steps"] = vm_result.stats["steps"]
    row["integrate_vm_s"] = vm_result.stats["run_time"]
    if ccodegen.find_compiler() is None:
        return row
    with tempfile.TemporaryDirectory() as cache:
        os.environ["DYADC_CACHE"] = cache
        began = time.perf_counter()
        native = compile_c(lower(reduced))
        row["c_build_s"] = time.perf_counter() - began
        row["c_s"], c_result = best_run(native)
        row["integrate_c_s"] = c_result.stats["run_time"]
        row["max_diff"] = float(abs(c_result.values - vm_result.values).max())
    return row


def main(argv: list[str]) -> None:
    sizes = [int(a) for a in argv] or [20, 100]
    print(f"{'model':>6} {'unknowns':>8} {'lower':>7} {'C build':>8} {'steps':>6} "
          f"{'VM total':>9} {'C total':>8} {'VM IDAS':>8} {'C IDAS':>7} {'max|diff|':>10}")
    for n, heavy in [(n, heavy) for heavy in (False, True) for n in sizes]:
        r = bench(n, heavy)
        print(f"{r['model']:>6} {r['n_unknowns']:>8} {r['lower_s']:>7.3f} {r.get('c_build_s', float('nan')):>8.2f} "
              f"{r['steps']:>6} {r['vm_s']:>9.3f} {r.get('c_s', float('nan')):>8.3f} "
              f"{r['integrate_vm_s']:>8.3f} {r.get('integrate_c_s', float('nan')):>7.3f} "
              f"{r.get('max_diff', float('nan')):>10.2e}")


if __name__ == "__main__":
    main(sys.argv[1:])
