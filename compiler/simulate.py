"""Runtime failures as located DyadErrors: the runtime knows nothing of sources, so a failure that
names an initial equation or a variable is pointed at it here."""
from __future__ import annotations

from contextlib import contextmanager
from typing import TYPE_CHECKING, Iterator, Mapping

from compiler import runtime
from compiler.errors import DyadError, Note, SimulationError, Span

if TYPE_CHECKING:
    from compiler.structure.reduced import ReducedSystem


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
