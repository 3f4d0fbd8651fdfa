"""Modelica's event constructs, which Dyad does not have, and what Dyad offers instead: a user
coming from Modelica who writes `when`, `reinit`, `pre` or `edge` is told that, not that a
multiplication lacks its `*` or that a function is unknown."""
from __future__ import annotations

from compiler.errors import DyadError, Span

_EVENTS = ("events come from conditions in relations: `x = ifelse(h < 0, a, b)` or an "
           "`if h < 0 ... else ... end` block; the solver locates each crossing of the condition "
           "as an event (docs/language.md)")

MODELICA_FORMS = {
    "when": ("`when` is Modelica: Dyad has no `when` equations", _EVENTS),
    "reinit": ("`reinit` is Modelica: Dyad does not reset a state at an event",
               "model the impact instead, e.g. a stiff contact force "
               "`F = ifelse(h < 0, -k * h - d * v, 0)`; " + _EVENTS),
    "pre": ("`pre` is Modelica: Dyad's relations hold at every instant and have no value "
            "'before the event'", _EVENTS),
    "edge": ("`edge` is Modelica: Dyad has no Boolean edges", "write the condition itself; " + _EVENTS),
}


def modelica_form_error(word: str, span: Span | None) -> DyadError | None:
    """The error for a Modelica event construct named `word`, or None for any other word."""
    found = MODELICA_FORMS.get(word)
    if found is None:
        return None
    message, hint = found
    return DyadError(message, span, hint=hint)
