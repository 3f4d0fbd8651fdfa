"""The whole compiler as one function per stage boundary, with timings for every stage."""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Sequence

from compiler.model.flat import FlatSystem
from compiler.lower.to_casadi import lower
from compiler.model.model_check import require_standalone
from compiler.runtime import CompiledModel
from compiler.lower.state_set_variants import build_variant, monitored_levels
from compiler.structure.reduce import Analysis, StructureReport, analyse, reduce
from compiler.structure.reduced import ReducedSystem


@dataclass
class Compilation:
    flat: FlatSystem
    reduced: ReducedSystem
    model: CompiledModel
    report: StructureReport
    timings: dict[str, float] = field(default_factory=dict)
    analysis: Analysis | None = None
    variant: object | None = None        # a dynamic.Variant when the state set may have to switch

    @property
    def dynamic(self) -> bool:
        return self.variant is not None


def flatten_spec(spec: str, lib_dirs: Sequence[str] = ()) -> tuple[FlatSystem, dict[str, float]]:
    from compiler.model.flatten import flatten_model
    began = time.perf_counter()
    flat = flatten_model(spec, list(lib_dirs))
    return flat, {"parse+flatten": time.perf_counter() - began}


def compile_flat(flat: FlatSystem, timings: dict[str, float] | None = None) -> Compilation:
    timings = dict(timings or {})
    report = StructureReport()
    began = time.perf_counter()
    require_standalone(flat)         # the checks `dyadc check` runs: both say the same
    analysis = analyse(flat)
    report.timings["alias+rank+index"] = time.perf_counter() - began
    reduced = reduce(flat, point=flat.initial_values(), report=report, analysis=analysis)
    timings["structure"] = time.perf_counter() - began
    began = time.perf_counter()
    variant = None
    if monitored_levels(flat, analysis, report):
        variant = build_variant(flat, analysis, None, reduced=reduced, report=report)
        model = variant.model
    else:
        model = lower(reduced)
    timings["lower"] = time.perf_counter() - began
    return Compilation(flat, reduced, model, report, timings, analysis, variant)


def compile_spec(spec: str, lib_dirs: Sequence[str] = ()) -> Compilation:
    flat, timings = flatten_spec(spec, lib_dirs)
    return compile_flat(flat, timings)
