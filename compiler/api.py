"""The Python API: what a user (or a test) calls instead of the command line."""
from __future__ import annotations

import time
from typing import Mapping, Sequence

from compiler import runtime
from compiler.model.flat import FlatSystem
from compiler.pipeline import Compilation, compile_spec, flatten_spec
from compiler.simulate import runtime_errors


def flatten(model_spec: str, lib_dirs: Sequence[str] = ()) -> FlatSystem:
    return flatten_spec(model_spec, lib_dirs)[0]


def compile(model_spec: str, lib_dirs: Sequence[str] = ()) -> Compilation:  # noqa: A001 - the verb users expect
    return compile_spec(model_spec, lib_dirs)


def simulate_compiled(compilation: Compilation, stop: float, *, start: float = 0.0, rtol: float = 1e-6,
                      atol: float = 1e-6, points: int = 501, saveat=None,
                      params: Mapping[str, float] | None = None, progress: bool | None = None,
                      integrator_options: Mapping | None = None, max_step: float | None = None,
                      max_steps: int = 100000) -> runtime.Result:
    """Run a compilation through the runtime's one driver (with the state-set switcher when its
    state set may have to change); failures become located DyadErrors. `integrator_options` go to
    CasADi's IDAS interface, e.g. {"suppress_algebraic": False} to keep the algebraic unknowns in
    the error test (default: suppressed, see compiler/runtime/idas.py)."""
    options = runtime.SimulationOptions(stop=stop, start=start, rtol=rtol, atol=atol, points=points,
                                        saveat=saveat, params=params, progress=progress,
                                        integrator_options=integrator_options, max_step=max_step,
                                        max_steps=max_steps)
    switcher = None
    if compilation.dynamic:
        from compiler.lower.state_set_variants import Switcher
        switcher = Switcher(compilation.flat, compilation.analysis, compilation.variant,
                            compilation.model)
    from compiler.model.run_checks import checked_run       # missing parameter values, singular start
    with checked_run(compilation, params, start), runtime_errors(compilation.reduced, compilation.flat):
        result = runtime.simulate(compilation.model, options=options, switcher=switcher)
    result.stats["compile_time"] = sum(compilation.timings.values())
    result.stats["compile_timings"] = dict(compilation.timings)
    return result


def simulate(model_spec: str, stop: float, *, lib_dirs: Sequence[str] = (), start: float = 0.0,
             rtol: float = 1e-6, atol: float = 1e-6, points: int = 501, saveat=None,
             params: Mapping[str, float] | None = None, progress: bool | None = None) -> runtime.Result:
    compilation = compile_spec(model_spec, lib_dirs)
    return simulate_compiled(compilation, stop, start=start, rtol=rtol, atol=atol, points=points,
                             saveat=saveat, params=params, progress=progress)
