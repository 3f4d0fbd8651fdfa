"""The Python API: what a user (or a test) calls instead of the command line.

Only the runtime is imported with this module; the compiler's stages are imported when a compile
runs (a run from the compilation cache imports neither sympy nor lark).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Mapping, Sequence

from compiler import runtime
from compiler.simulate import runtime_errors, translate_runtime_error

if TYPE_CHECKING:
    from compiler.cache.models import CachedCompilation
    from compiler.model.flat import FlatSystem
    from compiler.pipeline import Compilation


def flatten(model_spec: str, lib_dirs: Sequence[str] = ()) -> FlatSystem:
    from compiler.pipeline import flatten_spec
    return flatten_spec(model_spec, lib_dirs)[0]


def compile(model_spec: str, lib_dirs: Sequence[str] = ()) -> Compilation:  # noqa: A001 - the verb users expect
    from compiler.pipeline import compile_spec
    return compile_spec(model_spec, lib_dirs)


def simulate_compiled(compilation: Compilation | CachedCompilation, stop: float, *, start: float = 0.0,
                      rtol: float = 1e-6, atol: float = 1e-6, points: int = 501, saveat=None,
                      params: Mapping[str, float] | None = None, progress: bool | None = None,
                      integrator_options: Mapping | None = None, max_step: float | None = None,
                      max_steps: int = 100000, signals: Sequence[str] | None = None,
                      bounds: str = "warn") -> runtime.Result:
    """Run a compilation through the runtime's one driver (with the state-set switcher when its
    state set may have to change); failures become located DyadErrors. `integrator_options` go to
    CasADi's IDAS interface, e.g. {"suppress_algebraic": False} to keep the algebraic unknowns in
    the error test (default: suppressed, see compiler/runtime/idas.py). `bounds`: a declared
    min/max the run leaves gives a BoundWarning and the run goes on ("warn"), or stops it with a
    located error ("error"). A compilation from the
    cache runs its model alone; where a located error needs the sources (a parameter without a
    value, a failure at the start), the model is compiled from them and the run repeated."""
    arguments = dict(start=start, rtol=rtol, atol=atol, points=points, saveat=saveat, params=params,
                     progress=progress, integrator_options=integrator_options, max_step=max_step,
                     max_steps=max_steps, signals=signals, bounds=bounds)
    options = runtime.SimulationOptions(stop=stop, **arguments)
    if not hasattr(compilation, "flat"):
        return _simulate_cached(compilation, options, stop, arguments)
    switcher = None
    # else the model's own variants, or those made from its universal system (runtime/universal.py:
    # the same in-process, from the cache, in generated code and in sweep workers)
    if compilation.dynamic and not compilation.model.variants and compilation.model.universal is None:
        from compiler.lower.state_set_variants import Switcher
        switcher = Switcher(compilation.flat, compilation.analysis, compilation.variant,
                            compilation.model)
    from compiler.model.run_checks import checked_run       # missing parameter values, singular start
    with checked_run(compilation, params, start), runtime_errors(compilation.reduced, compilation.flat):
        result = runtime.simulate(compilation.model, options=options, switcher=switcher)
    return _with_compile_times(result, compilation.timings)


def _simulate_cached(cached: CachedCompilation, options: runtime.SimulationOptions, stop: float,
                     arguments: dict) -> runtime.Result:
    from compiler.pipeline import recompile

    def from_sources() -> runtime.Result:
        full = recompile(cached)
        full.model = cached.model          # the same model (maybe in C), now with its sources
        return simulate_compiled(full, stop, **arguments)

    given = arguments["params"] or {}
    if any(name not in given for name in cached.needs_values):
        return from_sources()                   # the located "has no value" error
    try:
        result = runtime.simulate(cached.model, options=options)
    except runtime.InitializationFailed:
        return from_sources()                   # located at the initial equations
    except runtime.SimulationFailed as err:
        if err.time_reached is None or err.time_reached <= options.start or err.variable is None:
            # maybe explained by a parameter value, or (a bare solver flag) by an operation
            # leaving its domain, which the sources locate (compiler/model/run_failures.py)
            return from_sources()
        raise translate_runtime_error(err, declarations=cached.declarations) from None
    except runtime.ModelInputError as err:
        if any(name not in cached.model.parameters for name in given):
            return from_sources()       # a structural parameter is named at its declaration
        raise translate_runtime_error(err) from None
    return _with_compile_times(result, cached.timings)


def _with_compile_times(result: runtime.Result, timings: Mapping[str, float]) -> runtime.Result:
    result.stats["compile_time"] = sum(timings.values())
    result.stats["compile_timings"] = dict(timings)
    return result


def simulate(model_spec: str, stop: float, *, lib_dirs: Sequence[str] = (), start: float = 0.0,
             rtol: float = 1e-6, atol: float = 1e-6, points: int = 501, saveat=None,
             params: Mapping[str, float] | None = None, progress: bool | None = None,
             cache: bool = False) -> runtime.Result:
    """Compile and run `model_spec`. `cache=True`: through the compilation cache, as
    `dyadc simulate` does (docs/cache.md)."""
    from compiler.pipeline import compile_or_load
    compilation = compile_or_load(model_spec, lib_dirs, cache=cache)
    return simulate_compiled(compilation, stop, start=start, rtol=rtol, atol=atol, points=points,
                             saveat=saveat, params=params, progress=progress)


def linearize(model_spec: str, *, inputs: Sequence[str] = (), outputs: Sequence[str] = (),
              at: float | None = None, steady: bool = False, op: Mapping[str, float] | None = None,
              params: Mapping[str, float] | None = None, opened: Sequence[str] = (),
              minimal: bool = False, lib_dirs: Sequence[str] = (), cache: bool = True):
    """The linear model (A, B, C, D) of `model_spec` at an operating point (the initial point, the
    state of a run at time `at`, or a steady state), from its free inputs or analysis points to any
    variables or analysis points: a compiler.linear.system.LinearSystem (docs/analysis.md)."""
    from compiler.linear.request import Request, linearize_spec
    request = Request(inputs=tuple(inputs), outputs=tuple(outputs), at=at, steady=steady,
                      op=dict(op or {}), params=dict(params or {}), opened=tuple(opened), minimal=minimal)
    return linearize_spec(model_spec, request, lib_dirs, cache=cache)
