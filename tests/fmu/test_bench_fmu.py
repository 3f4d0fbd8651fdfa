"""benchmarks/bench_fmu.py runs (so that `make bench` cannot rot): its figures for a small model
with an algebraic unknown, from the FMUs the other tests exported, one repeat."""
from __future__ import annotations

import sys
from pathlib import Path

from tests.fmu.conftest import MODELS

BENCHMARKS = Path(__file__).resolve().parents[2] / "benchmarks"


def test_bench_fmu_measures_and_renders(exported):
    sys.path.insert(0, str(BENCHMARKS))
    try:
        import bench_fmu
    finally:
        sys.path.remove(str(BENCHMARKS))
    fmus = {kind: exported("Fmu.TwoBodies", kind=kind) for kind in ("me", "cs")}
    found = bench_fmu.measure("Fmu.TwoBodies", [MODELS], 200.0, repeats=1, evaluations=50, fmus=fmus)
    assert found["costs"]["agreement"] <= 1e-12          # the FMU's der(x) is dyad_dae's
    assert found["runs"]["codegen"] == "c"
    table = bench_fmu.render(found)
    assert table.startswith(bench_fmu.BEGIN) and table.endswith(bench_fmu.END)
    assert "| FMPy, Co-Simulation FMU (the FMU's TR-BDF2) |" in table
    assert "| dyadc's C function `dyad_dae` (f and g at given x, z) |" in table
