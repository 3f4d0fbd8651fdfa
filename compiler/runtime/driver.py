"""The one simulation driver: the state-set switcher a model needs, consistent initialization,
the run loop (run_loop.py), and the Result (the part reached, when the run fails)."""
from __future__ import annotations

import time as _time

import numpy as np

from . import interrupts
from .errors import SimulationFailed, SimulationInterrupted
from .initialization import InitialPoint, consistent_initialization
from .model import CompiledModel
from .model_code import code_stats, on_its_code
from .native.choice import integrator_maker
from .options import SimulationOptions
from .progress import Progress
from .relations import settle_relations
from .result import Result
from .run_loop import integrate
from .run_state import RunState, StateSetSwitcher, switched_factor
from .segments import segment_ends, with_clock
from .static import solve_static
from .universal import UniversalSwitcher
from .variants import SELECTION, VariantSwitcher


def default_switcher(model: CompiledModel) -> StateSetSwitcher | None:
    """The switcher among the state sets a model carries: its compiled variants, or the ones made
    from its universal system (universal.py); None for a model with one state set."""
    if model.variants:
        return VariantSwitcher(model)
    if model.universal is not None and SELECTION in model.metadata:
        return UniversalSwitcher(model)
    return None


def simulate(model: CompiledModel, stop: float | None = None, *, options: SimulationOptions | None = None,
             switcher: StateSetSwitcher | None = None, **settings) -> Result:
    """Initialize consistently at the start, integrate to the stop, evaluate the outputs. A model
    that carries several state sets switches among them (default_switcher) unless the caller
    gives another switcher.

    Either pass `options` or the same settings as keywords (stop, start, points, saveat, rtol, atol,
    params, max_steps, max_step, breakpoints, integrator_options, progress, integrator). The
    integrator is the one choice of native/choice.py, whoever calls: the native IDAS driver where
    it can run the model, else CasADi's IDAS, named in `stats["integrator"]` with the reason in
    `stats["integrator_why"]`. A model whose code is not settled yet is put on it first
    (model_code.py: its C library built where a C compiler is present), reported in
    `stats["codegen"]` (and `["codegen_why"]`)."""
    if options is None:
        options = SimulationOptions(stop=stop, **settings)
    elif stop is not None or settings:
        raise TypeError("pass either options or keyword settings, not both")
    options = options.validated()
    model = on_its_code(model)               # after the options' checks: no build for a bad call
    run = RunState(model, options, switcher if switcher is not None else default_switcher(model),
                   integrator_maker(options.integrator))
    p = model.parameter_vector(options.params)
    run.parameters = model.named_parameters(p)
    run.ends = segment_ends(model, p, options)
    p = with_clock(model, p, options.start, run.ends[0])
    stats: dict = {"compile_time": model.compile_time, **code_stats(model)}
    began = _time.perf_counter()
    point = consistent_initialization(model, p, options.start)
    p, settled_z = settle_relations(model, p, point.x, point.z, options.start)
    point = InitialPoint(point.x, settled_z, point.iterations, point.residual)
    stats.update(init_time=_time.perf_counter() - began, init_iterations=point.iterations,
                 init_residual=point.residual)
    began = _time.perf_counter()
    progress = Progress(options.show_progress(), options.start, options.stop)
    with interrupts.watching():
        return _run_watched(run, model, p, point, progress, stats, began)


def _run_watched(run, model, p, point, progress, stats, began) -> Result:
    """The run from the consistent point (the run loop, or the algebraic solve of a model without
    states) while Ctrl-C is watched; a failure carries the part of the result reached."""
    try:
        if not model.state_names:
            run.values[:] = solve_static(model, run.grid, p, point.z, run.counters, progress)[
                [model.output_index(n) for n in run.public]]
        else:
            run.start_at(p, point.x, point.z)
            integrate(run, progress)
            run.finish()
    except KeyboardInterrupt:
        raise SimulationInterrupted(f"interrupted at t = {run.t:.10g}", float(run.t),
                                    "interrupted") from None
    except SimulationFailed as failure:
        failure.partial = _partial_result(run, model)
        raise
    except Exception:
        if interrupts.pending:              # CasADi's wrapper turns Ctrl-C into other errors
            raise SimulationInterrupted(f"interrupted at t = {run.t:.10g}", float(run.t),
                                        "interrupted") from None
        raise
    finally:
        progress.close()
    stats["run_time"] = _time.perf_counter() - began
    stats.update(run.counters)
    stats["state_switches"] = run.switches
    stats["integrator"] = ", ".join(sorted(run.integrator_names))
    if run.integrator_why:
        stats["integrator_why"] = "; ".join(run.integrator_why)
    if run.bounds_left:                   # declared bounds the run left and went on (bounds="warn")
        stats["bounds_left"] = run.bounds_left
    if run.switches:                      # what IDAS ran at from the first switch on
        stats["rtol_after_first_switch"] = run.options.rtol / switched_factor(run.options.rtol)
    return _result(run, model, len(run.grid), stats)


def _result(run: RunState, model: CompiledModel, n: int, stats: dict) -> Result:
    """The first n output times of the run as a Result."""
    units = model.metadata.get("units") or {}
    return Result(run.grid[:n], run.public, run.values[:, :n], stats, model.name,
                  units={name: units[name] for name in run.public if name in units},
                  events=run.events, switches=run.switches, parameters=run.parameters)


def _partial_result(run: RunState, model: CompiledModel) -> Result | None:
    """The output times the run had reached when it failed, as a Result (None if not even one)."""
    try:
        run.finish()
    except Exception:                       # the failure itself may have left bad points behind
        return None
    filled = ~np.isnan(run.values).all(axis=0) if run.values.size else np.zeros(0, dtype=bool)
    n = int(np.argmin(filled)) if not filled.all() else len(filled)
    return _result(run, model, n, dict(run.counters)) if n else None
