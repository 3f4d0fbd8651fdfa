"""The Python API: what a user (or a test) calls instead of the command line."""
from __future__ import annotations

import time
from typing import Mapping, Sequence

from compiler import runtime
from compiler.errors import DyadError, SimulationError
from compiler.flat import FlatSystem
from compiler.pipeline import Compilation, compile_spec, flatten_spec


def flatten(model_spec: str, lib_dirs: Sequence[str] = ()) -> FlatSystem:
    return flatten_spec(model_spec, lib_dirs)[0]


def compile(model_spec: str, lib_dirs: Sequence[str] = ()) -> Compilation:  # noqa: A001 - the verb users expect
    return compile_spec(model_spec, lib_dirs)


def simulate_compiled(compilation: Compilation, stop: float, *, start: float = 0.0, rtol: float = 1e-6,
                      atol: float = 1e-6, points: int = 501, saveat=None,
                      params: Mapping[str, float] | None = None, progress: bool | None = None,
                      integrator_options: Mapping | None = None) -> runtime.Result:
    """`integrator_options` go to CasADi's IDAS interface, e.g. {"suppress_algebraic": False} to keep
    the algebraic unknowns in the error test (default: suppressed, see compiler/runtime.py)."""
    try:
        if compilation.dynamic:
            from compiler.dynamic import simulate_dynamic
            result = simulate_dynamic(compilation.flat, compilation.analysis, compilation.variant, stop,
                                      start=start, rtol=rtol, atol=atol, points=points, saveat=saveat,
                                      params=params, integrator_options=integrator_options)
        else:
            result = runtime.simulate(compilation.model, stop, start=start, rtol=rtol, atol=atol, points=points,
                                      saveat=saveat, params=params, progress=progress,
                                      integrator_options=integrator_options)
    except runtime.SimulationFailed as err:
        raise SimulationError(str(err), getattr(err, "time_reached", None), getattr(err, "reason", None)) from None
    except runtime.ModelInputError as err:
        raise DyadError(str(err)) from None
    result.stats["compile_time"] = sum(compilation.timings.values())
    result.stats["compile_timings"] = dict(compilation.timings)
    return result


def simulate(model_spec: str, stop: float, *, lib_dirs: Sequence[str] = (), start: float = 0.0,
             rtol: float = 1e-6, atol: float = 1e-6, points: int = 501, saveat=None,
             params: Mapping[str, float] | None = None, progress: bool | None = None) -> runtime.Result:
    compilation = compile_spec(model_spec, lib_dirs)
    return simulate_compiled(compilation, stop, start=start, rtol=rtol, atol=atol, points=points,
                             saveat=saveat, params=params, progress=progress)
