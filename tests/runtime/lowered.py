"""Hand-built ReducedSystems (runtime_systems.py) lowered and run: what the pipeline does after
its structural passes, without a source file."""
from __future__ import annotations

import time

from compiler import runtime
from compiler.cache.c_code import compile_c, on_vm
from compiler.errors import DyadError
from compiler.lower.to_casadi import lower
from compiler.runtime import CompiledModel, Result
from compiler.simulate import runtime_errors
from compiler.structure.reduced import ReducedSystem


def compile_model(reduced: ReducedSystem, codegen: str | None = None) -> CompiledModel:
    """Lower `reduced`; `codegen='c'` compiles its DAE to a shared library (compiler/cache/c_code.py),
    `codegen='vm'` puts it on CasADi's VM, None leaves its code to its first run (which builds C
    where a C compiler is present: compiler/runtime/model_code.py)."""
    began = time.perf_counter()
    model = lower(reduced)
    if codegen == "vm":
        model = on_vm(model)
    elif codegen not in (None, "", "none"):
        if codegen != "c":
            raise DyadError(f"unknown code generation target '{codegen}' (expected 'c', 'vm' or none)")
        model = compile_c(model)
    model.compile_time = time.perf_counter() - began
    return model


def simulate_model(model: CompiledModel, stop: float, reduced: ReducedSystem | None = None,
                   **options) -> Result:
    """runtime.simulate with failures as DyadErrors; `reduced` (optional) locates init residuals."""
    with runtime_errors(reduced):
        return runtime.simulate(model, stop, **options)


def simulate_reduced(reduced: ReducedSystem, stop: float, *, codegen: str | None = None,
                     **options) -> Result:
    return simulate_model(compile_model(reduced, codegen), stop, reduced, **options)
