"""Run a compilation through the runtime (`simulate_compiled`, which compiler.api offers), with its
failures as located DyadErrors: the runtime knows nothing of sources, so a failure that names an
initial equation or a variable is pointed at it here."""
from __future__ import annotations

from contextlib import contextmanager
from typing import TYPE_CHECKING, Iterator, Mapping, Sequence

from compiler import runtime
from compiler.errors import DyadError, Note, SimulationError, Span

if TYPE_CHECKING:
    from compiler.cache.models import CachedCompilation
    from compiler.pipeline import Compilation
    from compiler.structure.reduced import ReducedSystem


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
    from compiler.run_checks import checked_run       # missing parameter values, singular start
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


@contextmanager
def runtime_errors(reduced: ReducedSystem | None = None, flat=None) -> Iterator[None]:
    """Translate runtime exceptions (which know nothing of sources) into DyadErrors with spans;
    with `flat`, a failure that names a variable (a bound, a runaway value) points at its
    declaration."""
    try:
        yield
    except (runtime.InitializationFailed, runtime.SimulationFailed, runtime.ModelInputError) as err:
        raise translate_runtime_error(err, reduced, _declarations(flat)) from None


def translate_runtime_error(err: Exception, reduced: ReducedSystem | None = None,
                            declarations: Mapping[str, Span] | None = None) -> DyadError:
    """The DyadError for a runtime failure: initial residuals located with `reduced`, a failure
    naming a variable at its declaration in `declarations` (name -> span)."""
    if isinstance(err, runtime.InitializationFailed):
        origins = reduced.initial.origins if reduced is not None else []
        notes = []
        for index, value, label in err.worst:
            origin = origins[index] if index < len(origins) else None
            if origin is not None and getattr(origin, "span", None) is not None:
                notes.append(Note(f"this initial condition ({origin.path or '<model>'}) is off by "
                                  f"{value:.6g}", origin.span))
            else:
                notes.append(Note(f"{label} is off by {value:.6g}"))
        error = SimulationError(str(err).split("\n")[0].replace("; largest residuals:", ""),
                                err.time_reached, err.reason,
                                hint="check the initial equations and values named in the notes; "
                                     "guesses only seed the solver")
        error.notes = notes
        return error
    if isinstance(err, runtime.SimulationFailed):
        error = SimulationError(str(err), err.time_reached, err.reason,
                                hint="check the model near that time: an algebraic equation may have lost its "
                                     "solution or a variable left its valid range; a stiff run "
                                     "may need a larger max_steps")
        error.partial = err.partial
        span = (declarations or {}).get(err.variable) if err.variable is not None else None
        if span is not None:
            error.notes = [Note(f"`{err.variable}` is declared here", span)]
        return error
    return DyadError(str(err))


def _declarations(flat) -> dict[str, Span] | None:
    """name -> declaration span of `flat`'s variables (built only when a run failed)."""
    if flat is None:
        return None
    spans = {}
    for variable in flat.variables:
        span = getattr(variable.origin, "span", None)
        if span is not None:
            spans.setdefault(variable.name, span)
    return spans
