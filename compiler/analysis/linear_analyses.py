"""Reading Dyad's linear analyses (`LinearAnalysis`, `ClosedLoopAnalysis`,
`ClosedLoopSensitivityAnalysis`, from DyadControlSystems) into plain settings.

    analysis MotorLoop
      extends ClosedLoopAnalysis(measurement = "y", control_input = "u", wl = 0.1, wu = 1000)
      model = MotorWithController()
    end

Names are analysis points of the model (or, for LinearAnalysis, free top-level inputs and any
variable). Fields and defaults follow Dyad's documentation: frequencies wl, wu in rad/s (-1: chosen
from the model's poles), `pos_feedback = true` (the model's loop carries the feedback sign, as
Dyad's blocks do: the controller is the negated map from measurement to control input),
`duration` of the step responses in s (-1: chosen from the poles).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Mapping

from compiler.analysis.expressions import AnalysisValues, substitute
from compiler.analysis.transient import analysis_model, collect_analysis
from compiler.errors import DyadError, Span, suggest_name
from compiler.model.expressions import Lexical
from compiler.model.library import Library, Resolved
from compiler.syntax import ast

REQUIRED = object()
FIELDS: dict[str, dict[str, Any]] = {
    "LinearAnalysis": {"inputs": REQUIRED, "outputs": REQUIRED, "loop_openings": (), "duration": -1.0},
    "ClosedLoopAnalysis": {"measurement": REQUIRED, "control_input": REQUIRED, "loop_openings": (),
                           "wl": -1.0, "wu": -1.0, "num_frequencies": 3000, "pos_feedback": True,
                           "duration": -1.0},
    "ClosedLoopSensitivityAnalysis": {"analysis_points": REQUIRED, "loop_openings": (),
                                      "wl": -1.0, "wu": -1.0},
}
KINDS = tuple(FIELDS)


@dataclass(frozen=True)
class LinearAnalysisRun:
    name: str                       # qualified name of the analysis
    kind: str                       # one of KINDS
    model: Resolved                 # the component to flatten (extends the analysis's model)
    model_name: str
    settings: Mapping[str, Any]     # every field of the kind, given or defaulted
    span: Span | None = None
    parameters: frozenset[str] = frozenset()
    spans: Mapping[str, Span | None] = None        # where each given field is written


def linear_kind(resolved: Resolved, library: Library) -> str | None:
    """The linear-analysis kind at the root of `resolved`'s chain, or None."""
    kind = collect_analysis(resolved, library, ()).root
    return kind if kind in FIELDS else None


def read_linear(resolved: Resolved, library: Library, overrides: Mapping[str, float] | None = None
                ) -> LinearAnalysisRun:
    definition = resolved.definition
    collected = collect_analysis(resolved, library, ())
    kind = collected.root
    fields = FIELDS[kind]
    values = dict(collected.values)
    for name, value in (overrides or {}).items():
        if name in collected.parameters or name in fields:
            values[name] = ast.Number(value)
    unknown = sorted(set(values) - set(fields) - collected.parameters)
    if unknown:
        close = suggest_name(unknown[0], sorted(fields))
        raise DyadError(f"`{kind}` has no field `{unknown[0]}`", collected.spans.get(unknown[0])
                        or definition.span, hint=close or f"its fields: {', '.join(fields)}")
    scope = {name: value for name, value in values.items() if value is not None}
    evaluated = AnalysisValues(definition.name, scope, Lexical(library, resolved.package, resolved.file))
    settings = {}
    for name, default in fields.items():
        where = collected.spans.get(name) or definition.span
        if name not in scope:
            if default is REQUIRED:
                raise DyadError(f"analysis `{definition.name}` ({kind}) gives no `{name}`",
                                definition.span, hint=f"extends {kind}({name} = ...)")
            settings[name] = default
            continue
        settings[name] = _value(substitute(scope[name], scope), default, f"`{name}` of analysis "
                                f"`{definition.name}`", where, lambda what: evaluated.number(name, what, where))
    model, model_name = analysis_model(resolved, collected, scope)
    return LinearAnalysisRun(resolved.qualified_name, kind, model, model_name, settings,
                             definition.span, frozenset(collected.parameters), dict(collected.spans))


# what each name field may name: analysis points, free top-level inputs, variables
NAMED = {"inputs": ("points", "free"), "outputs": ("points", "variables"), "loop_openings": ("points",),
         "measurement": ("points",), "control_input": ("points",), "analysis_points": ("points",)}


def check_names(run: LinearAnalysisRun, flat) -> None:
    """Every name the analysis gives exists in its model, or a located error at the field."""
    from compiler.linear.inputs import analysis_points, free_inputs
    known = {"points": set(analysis_points(flat)), "free": set(free_inputs(flat)),
             "variables": {v.name for v in flat.variables}}
    kinds = {"points": "an analysis point", "free": "a free top-level input", "variables": "a variable"}
    for field, allowed in NAMED.items():
        if field not in run.settings:
            continue
        given = run.settings[field]
        for name in ((given,) if isinstance(given, str) else given):
            candidates = set().union(*(known[a] for a in allowed))
            if name in candidates:
                continue
            close = suggest_name(name, sorted(candidates))
            what = " or ".join(kinds[a] for a in allowed)
            raise DyadError(f"`{name}` in `{field}` of analysis `{run.name}` is not {what} of "
                            f"`{run.model_name}`" + (f"; {close}" if close else ""),
                            run.spans.get(field) or run.span,
                            hint=f"its analysis points: {', '.join(sorted(known['points'])) or 'none'}")


def _value(expr: Any, default: Any, what: str, span: Span | None, number: Callable[[str], float]) -> Any:
    """A field's value, of the type of its default (names: a list of strings; a name: a string);
    `number(what)` evaluates a numeric field with the guarded evaluator."""
    if default is REQUIRED or isinstance(default, tuple):
        if isinstance(expr, ast.String) and default is REQUIRED:
            return expr.value
        if isinstance(expr, ast.ArrayLit) and all(isinstance(e, ast.String) for e in expr.elements):
            return tuple(e.value for e in expr.elements)
        raise DyadError(f"{what} must be {'a name or ' if default is REQUIRED else ''}a list of "
                        f"names in quotes, e.g. [\"y\"]", getattr(expr, "span", None) or span)
    if isinstance(default, bool):
        if isinstance(expr, ast.Boolean):
            return expr.value
        raise DyadError(f"{what} must be true or false", getattr(expr, "span", None) or span)
    value = number(what)
    if isinstance(default, int):
        if value != int(value) or value < 2:
            raise DyadError(f"{what} must be a whole number of at least 2", getattr(expr, "span", None) or span)
        return int(value)
    return value
