"""Checks that need the run's parameter values (the defaults with the caller's overrides), so they
cannot be made when compiling: every used parameter has a value before the run, and a run that
fails at its start is explained when a parameter value makes the index-1 system singular.

`checked_run(compilation, params, start)` wraps a run (compiler/api.py):

    with checked_run(compilation, params, start), runtime_errors(compilation.reduced):
        result = runtime.simulate(...)
"""
from __future__ import annotations

from contextlib import contextmanager
from typing import Iterator, Mapping

from compiler.errors import DyadError, Note, SimulationError
from compiler.model.parameter_checks import require_parameter_values, require_tunable_overrides
from compiler.structure.diagnostics import parameter_singularity_error


@contextmanager
def checked_run(compilation, params: Mapping | None, start: float, run=None) -> Iterator[None]:
    require_tunable_overrides(compilation.flat, params)
    require_parameter_values(compilation.flat, {p.name for p in compilation.reduced.parameters},
                             params)
    try:
        yield
    except SimulationError as err:
        explained = None
        if err.time_reached is None or err.time_reached <= start:
            explained = explain_start_failure(compilation, params)
        if explained is None and err.span is None and not err.notes:
            # a bare solver flag: look for an operation that left its domain (run_failures.py)
            from compiler.model.run_failures import diagnose
            try:
                values = run_parameter_values(compilation, params)
            except (TypeError, ValueError):
                values = {}
            raise diagnose(err, compilation, values, start, run) from None
        if explained is None:
            raise
        explained.notes.append(Note(f"the solver reported: {err.message}"))
        raise explained from None


def run_parameter_values(compilation, params: Mapping | None) -> dict[str, float]:
    """Defaults, overrides, and the bound parameters re-derived from them in dependency order."""
    params = dict(params or {})
    values: dict[str, float] = {}
    for info in compilation.reduced.parameters:
        if info.name in params:
            values[info.name] = float(params[info.name])
        elif info.binding is not None:
            import sympy
            bound = sympy.sympify(info.binding.xreplace({sympy.Symbol(k): v for k, v in values.items()}))
            values[info.name] = float(bound) if bound.is_number else float(info.value)
        else:
            values[info.name] = float(info.value)
    return values


def explain_start_failure(compilation, params: Mapping | None) -> DyadError | None:
    analysis = compilation.analysis
    if analysis is None:
        return None
    try:
        values = run_parameter_values(compilation, params)
    except (TypeError, ValueError):
        return None
    system = analysis.system
    states = set(compilation.reduced.states)
    unknown_mask = [name not in states for name in system.names]
    return parameter_singularity_error(system, unknown_mask, values)
