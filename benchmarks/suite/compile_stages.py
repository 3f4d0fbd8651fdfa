"""Stage times of one compilation, meant to run in a fresh process (`python compile_stages.py`).

    python benchmarks/suite/compile_stages.py model SPEC STOP     -> one JSON line
    python benchmarks/suite/compile_stages.py chain BUDGET N...   -> one JSON line per N

Stages: import (the compiler, sympy, casadi), parse (every .dyad file the model needs, including
building the LALR parser in a cold process), flatten (instantiation and flattening without the
parsing), structure (alias elimination, index reduction, causalization), lower (CasADi
functions), simulate (first run on CasADi's VM: initialization, IDAS, outputs) and, for the
model, the uncached C build of the DAE and its Jacobian.
"""
from __future__ import annotations

import json
import os
import sys
import tempfile
import time
from pathlib import Path

STARTED = time.perf_counter()
ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from compiler import runtime  # noqa: E402

from compiler.cache.c_code import build_library, on_vm
from compiler.lower import ccodegen
from compiler.model.flatten import flatten_resolved  # noqa: E402
from compiler.model.library import Library  # noqa: E402
from compiler.model.model_spec import resolve_model  # noqa: E402
from compiler.pipeline import compile_flat  # noqa: E402
from compiler.syntax.parser import parse_file  # noqa: E402

IMPORT_SECONDS = time.perf_counter() - STARTED


def stage_times(spec: str, stop: float, points: int, with_c: bool) -> dict:
    parse_seconds = [0.0]

    def timed_parse(path):
        began = time.perf_counter()
        try:
            return parse_file(path)
        finally:
            parse_seconds[0] += time.perf_counter() - began

    began = time.perf_counter()
    library = Library(parser=timed_parse)
    flat = flatten_resolved(resolve_model(spec, library), library)
    parse_and_flatten = time.perf_counter() - began
    compilation = compile_flat(flat)
    row = {"parse": parse_seconds[0], "flatten": parse_and_flatten - parse_seconds[0],
           "structure": compilation.timings["structure"], "lower": compilation.timings["lower"],
           "structure_detail": dict(getattr(compilation.report, "timings", {}) or {}),
           "equations": len(flat.equations), "states": len(compilation.model.state_names),
           "algebraics": len(compilation.model.algebraic_names)}
    began = time.perf_counter()
    # on the VM, as this stage was measured before a run settled an undecided model on C (its build
    # is timed apart, c_build, below)
    result = runtime.simulate(on_vm(compilation.model), stop, rtol=1e-6, atol=1e-6, points=points,
                              progress=False)
    row["simulate"] = time.perf_counter() - began
    row["steps"] = int(result.stats.get("steps", 0))
    if with_c and ccodegen.find_compiler():
        with tempfile.TemporaryDirectory(prefix="dyadc-bench-cache-") as cache:
            began = time.perf_counter()
            build_library(ccodegen.c_source(compilation.model), ccodegen.find_compiler(), Path(cache))
            row["c_build"] = time.perf_counter() - began
    return row


def main(argv: list[str]) -> None:
    if argv[0] == "model":
        row = stage_times(argv[1], float(argv[2]), 1201, with_c=True)
        row["import"] = IMPORT_SECONDS
        row["process"] = time.perf_counter() - STARTED
        print(json.dumps(row), flush=True)
        return
    from suite.chain_model import write_chain
    budget, sizes = float(argv[1]), [int(a) for a in argv[2:]]
    with tempfile.TemporaryDirectory(prefix="dyadc-chain-") as tmp:
        stage_times(write_chain(1, Path(tmp)), 0.5, 51, with_c=False)      # warm-up: parser, caches
        spent, last = 0.0, []
        for n in sizes:
            if len(last) >= 2 and spent + last[-1] * max(last[-1] / last[-2], 1.0) > budget:
                print(json.dumps({"n": n, "skipped": f"predicted beyond the {budget:.0f} s budget"}), flush=True)
                continue
            began = time.perf_counter()
            row = stage_times(write_chain(n, Path(tmp)), 0.5, 51, with_c=False)
            elapsed = time.perf_counter() - began
            spent += elapsed
            last.append(elapsed)
            row["n"] = n
            print(json.dumps(row), flush=True)


if __name__ == "__main__":
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    main(sys.argv[1:])
