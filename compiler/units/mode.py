"""What a unit finding does: `error` (the default: the first finding is the located error, the
model is refused), `warn` (each is a UnitWarning and the command goes on) or `off` (no check).
`units_mode(MODE)` sets it for the compilations in a block (the CLI's --units, the Python API's
`units=`), as size_limits.element_limit does for --max-elements.
"""
from __future__ import annotations

import warnings
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any, Iterator

from compiler.errors import DyadError, Note
from compiler.units.findings import Finding

MODES = ("error", "warn", "off")
DEFAULT_MODE = "error"
HELP = ("unit check of every equation, binding and connect: a mismatch is an error (default), a "
        "warning, or not checked (docs/language.md, Units)")
_configured: ContextVar[str | None] = ContextVar("dyadc_units", default=None)


class UnitWarning(UserWarning):
    """A unit finding under `--units warn`: the located message, rendered as the compiler's."""
    located = True          # its text starts with FILE:LINE:COL: warning: (compiler/cli.py)


@contextmanager
def units_mode(mode: str | None) -> Iterator[None]:
    """Use `mode` (None: the default, `error`) for the compilations in this block."""
    if mode is not None and mode not in MODES:
        raise DyadError(f"--units must be one of {', '.join(MODES)}, got `{mode}`")
    token = _configured.set(mode)
    try:
        yield
    finally:
        _configured.reset(token)


def current_mode() -> str:
    return _configured.get() or DEFAULT_MODE


def checked(model: Any) -> list[Finding] | None:
    """The unit findings of an instantiated model, reported as the current mode says; None when
    the check is off (nothing was checked)."""
    if current_mode() == "off":
        return None
    from compiler.units.check import check_units
    try:
        findings = check_units(model)
    except DyadError:
        raise
    except Exception as err:        # a bug of the check must not stop a model that flattened
        warnings.warn(f"the unit check stopped on an internal error ({type(err).__name__}: {err}) "
                      f"and checked nothing; this is a bug in dyadc", stacklevel=2)
        return None
    report(findings)
    return findings


def report(findings: list[Finding] | None) -> None:
    """Raise the first finding (mode `error`) or warn each (mode `warn`)."""
    mode = current_mode()
    if not findings or mode == "off":
        return
    if mode == "error":
        error = findings[0].error()
        if len(findings) > 1:
            error.notes.append(Note(f"{len(findings) - 1} more unit finding(s) in this model; "
                                    f"--units warn lists them all and goes on"))
        raise error
    for finding in findings:
        warnings.warn(UnitWarning(finding.error().format().replace(": error: ", ": warning: ", 1)),
                      stacklevel=2)
