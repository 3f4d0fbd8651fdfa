"""Running a compilation (in-process or from the cache) through the runtime, its failures made
located errors: the one run path shared by the Python API, the CLI and linear analysis."""

from __future__ import annotations

from typing import TYPE_CHECKING, Mapping, Sequence

from compiler import runtime
from compiler.runtime.native.choice import integrator_maker
from compiler.simulate import runtime_errors, translate_runtime_error

if TYPE_CHECKING:
    from compiler.cache.models import CachedCompilation
    from compiler.pipeline import Compilation


def simulate_compiled(compilation: Compilation | CachedCompilation, stop: float, *, start: float = 0.0,
                      rtol: float = 1e-6, atol: float = 1e-6, points: int = 501, saveat=None,
                      params: Mapping[str, float] | None = None, progress: bool | None = None,
                      integrator_options: Mapping | None = None, max_step: float | None = None,
                      max_steps: int = 100000, signals: Sequence[str] | None = None,
                      bounds: str = "warn", integrator=None, codegen: str | None = None) -> runtime.Result:
    """Run a compilation through the runtime's one driver (with the state-set switcher when its
    state set may have to change); failures become located DyadErrors. `integrator_options` go to
    CasADi's IDAS interface, e.g. {"suppress_algebraic": False} to keep the algebraic unknowns in
    the error test (default: suppressed, see compiler/runtime/idas.py). `bounds`: a declared
    min/max the run leaves gives a BoundWarning and the run goes on ("warn"), or stops it with a
    located error ("error"). `integrator`: "native", "casadi", a maker of integrators
    (SimulationOptions), or None: $DYADC_INTEGRATOR, else the native IDAS driver where it can run
    the model and CasADi's IDAS where not, reported as `result.stats["integrator"]` and
    `["integrator_why"]` (compiler/runtime/native/choice.py). The model runs on the code chosen
    for it (compiler/cache/native.py: compiled C where a C compiler is present, built now if need
    be; `codegen` "c" or "vm" asks for one), reported as `result.stats["codegen"]`. A compilation from the
    cache runs its model alone; where a located error needs the sources (a parameter without a
    value, a failure at the start), the model is compiled from them and the run repeated."""
    arguments = dict(start=start, rtol=rtol, atol=atol, points=points, saveat=saveat, params=params,
                     progress=progress, integrator_options=integrator_options, max_step=max_step,
                     max_steps=max_steps, signals=signals, bounds=bounds, integrator=integrator)
    options = runtime.SimulationOptions(stop=stop, **{**arguments, "integrator": integrator_maker(integrator)})
    model = model_for_runs(compilation, codegen)
    if not hasattr(compilation, "flat"):
        return _simulate_cached(compilation, model, options, stop, arguments)
    # a model switches among its own variants, or those made from its universal system
    # (runtime/universal.py: the same in-process, from the cache, in generated code and in sweep workers)
    from compiler.run_checks import checked_run       # missing parameter values, singular start
    # (a failure's diagnosis repeats the run towards it on the same model and integrator)
    with checked_run(compilation, params, start, (model, options.integrator)), \
            runtime_errors(compilation.reduced, compilation.flat):
        result = runtime.simulate(model, options=options)
    return _with_compile_times(result, compilation.timings)


def model_for_runs(compilation: Compilation | CachedCompilation, codegen: str | None):
    """The model the runs of `compilation` take, on their code (model_on_its_code), the time a
    build took recorded in the compilation's timings ("C code")."""
    return model_on_its_code(compilation.model, codegen, compilation.timings)


def model_on_its_code(model, codegen: str | None = None, timings: dict | None = None):
    """`model` on the code its runs take: the model itself when its code was chosen, else a copy
    put on it once (kept with the model: every run of the same model gets the same object, and what
    a run derives, say a state set made from the universal system, is kept in it for the next).
    `codegen` "c", "vm" or None ($DYADC_CODEGEN, else C where a C compiler is present)."""
    from compiler.cache.codegen_choice import requested
    current = model.metadata.get("codegen")
    if current is not None and codegen in (None, current):
        return model
    codegen = requested(codegen)          # $DYADC_CODEGEN when not given

    def put_on_code():
        import time
        from compiler.cache.native import start
        began = time.perf_counter()
        chosen = start(model, codegen).finish()
        if timings is not None:
            timings["C code"] = time.perf_counter() - began
        return chosen
    return model.derived(("on its code", codegen), put_on_code)


def _simulate_cached(cached: CachedCompilation, model, options: runtime.SimulationOptions, stop: float,
                     arguments: dict) -> runtime.Result:
    from compiler.pipeline import recompile

    def from_sources() -> runtime.Result:
        full = recompile(cached)
        full.model = model          # the same model on the same code, now with its sources
        return simulate_compiled(full, stop, **arguments)

    given = arguments["params"] or {}
    if any(name not in given for name in cached.needs_values):
        return from_sources()                   # the located "has no value" error
    try:
        result = runtime.simulate(model, options=options)
    except runtime.InitializationFailed:
        return from_sources()                   # located at the initial equations
    except runtime.SimulationFailed as err:
        if err.time_reached is None or err.time_reached <= options.start or err.variable is None:
            # maybe explained by a parameter value, or (a bare solver flag) by an operation
            # leaving its domain, which the sources locate (compiler/model/run_failures.py)
            return from_sources()
        raise translate_runtime_error(err, declarations=cached.declarations) from None
    except runtime.ModelInputError as err:
        if any(name not in model.parameters for name in given):
            return from_sources()       # a structural parameter is named at its declaration
        raise translate_runtime_error(err) from None
    return _with_compile_times(result, cached.timings)


def _with_compile_times(result: runtime.Result, timings: Mapping[str, float]) -> runtime.Result:
    result.stats["compile_time"] = sum(timings.values())
    result.stats["compile_timings"] = dict(timings)
    return result
