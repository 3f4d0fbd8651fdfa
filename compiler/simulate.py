"""Compiler-side entry points to the runtime: lower, simulate, and translate runtime failures into
located DyadErrors."""
from __future__ import annotations

import time
from contextlib import contextmanager
from typing import Iterator

from compiler import runtime
from compiler.errors import DyadError, Note, SimulationError
from compiler.lower.to_casadi import lower
from compiler.runtime import CompiledModel, Result
from compiler.structure.reduced import ReducedSystem


def compile_model(reduced: ReducedSystem, codegen: str | None = None) -> CompiledModel:
    """Lower `reduced`; `codegen='c'` compiles the DAE to a shared library (see ccodegen)."""
    began = time.perf_counter()
    model = lower(reduced)
    if codegen not in (None, "", "none", "vm"):
        if codegen != "c":
            raise DyadError(f"unknown code generation target '{codegen}' (expected 'c' or none)")
        from compiler.lower.ccodegen import compile_c
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


@contextmanager
def runtime_errors(reduced: ReducedSystem | None = None, flat=None) -> Iterator[None]:
    """Translate runtime exceptions (which know nothing of sources) into DyadErrors with spans;
    with `flat`, a failure that names a variable (a bound, a runaway value) points at its
    declaration."""
    try:
        yield
    except runtime.InitializationFailed as err:
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
        raise error from None
    except runtime.SimulationFailed as err:
        error = SimulationError(str(err), err.time_reached, err.reason,
                                hint="check the model near that time: an algebraic equation may have lost its "
                                     "solution or a variable left its valid range; a stiff run "
                                     "may need a larger max_steps")
        error.partial = err.partial
        span = _declaration(flat, err.variable)
        if span is not None:
            error.notes = [Note(f"`{err.variable}` is declared here", span)]
        raise error from None
    except runtime.ModelInputError as err:
        raise DyadError(str(err)) from None



def _declaration(flat, name: str | None):
    """The source span of the declaration of variable `name` in `flat`, when known."""
    if flat is None or name is None:
        return None
    for variable in flat.variables:
        if variable.name == name:
            return getattr(variable.origin, "span", None)
    return None
