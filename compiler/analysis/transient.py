"""Reading a Dyad `analysis` block into a transient run.

    analysis RLCTransient
      extends TransientAnalysis(stop = 10, abstol = 10m, reltol = 1m)
      parameter R0::Resistance = 100
      model = RLCModel(resistor.R = R0)
    end

The fields are Dyad's TransientAnalysis ones (start, stop, abstol, reltol, saveat, dtmax, alg, ...;
see FIELDS); an analysis may extend another analysis of the library path, whose fields and
parameters it inherits and may modify. The model to run is a new component that extends the
analysis's model with its modifiers (analysis parameters substituted), so that its variables keep
their own names (`resistor.v`, not `model.resistor.v`). Other analysis kinds (steady state,
linearization, PID autotuning, ...) are refused with a located error naming what dyadc runs.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

from compiler.analysis.expressions import AnalysisValues, substitute, text
from compiler.errors import DyadError, Span, suggest_name
from compiler.model.expressions import Lexical
from compiler.model.library import Library, Resolved, qualify
from compiler.model.model_spec import parse_spec_file, split_file_spec
from compiler.syntax import ast

TRANSIENT = "TransientAnalysis"
# Dyad's TransientAnalysis fields: the numeric ones dyadc uses, with their Dyad defaults, and
# the ones it accepts without effect (Julia's integrator choice, logging, code optimization).
NUMERIC_FIELDS = {"start": 0.0, "abstol": 1e-6, "reltol": 1e-6, "saveat": 0.0, "dtmax": 0.0}
IGNORED_FIELDS = {"alg", "tstops", "IfLifting", "progress", "verbose", "log_file",
                  "automatic_discontinuity_detection", "optimize", "respecialize"}
FIELDS = {"stop", *NUMERIC_FIELDS, *IGNORED_FIELDS}


@dataclass(frozen=True)
class TransientRun:
    name: str                           # qualified name of the analysis
    model: Resolved                     # the component to flatten (extends the analysis's model)
    model_name: str                     # the analysis's model type, as written
    stop: float
    start: float = 0.0
    abstol: float = 1e-6
    reltol: float = 1e-6
    saveat: float = 0.0                 # > 0: output every saveat; 0: dyadc's output grid
    dtmax: float = 0.0                  # > 0: largest integrator step; 0: no limit
    notes: tuple[str, ...] = ()
    span: Span | None = None
    parameters: frozenset[str] = frozenset()    # the analysis's own parameters (and inherited)


@dataclass
class CollectedAnalysis:
    """What the chain of analyses says, most derived last: field and parameter expressions by
    name, the model declaration, and the kind at the root of the chain."""
    values: dict[str, Any] = field(default_factory=dict)
    spans: dict[str, Span | None] = field(default_factory=dict)
    parameters: set[str] = field(default_factory=set)
    model: Any = None
    kind: str = ""
    root: str = ""                      # the kind at the root of the chain (LinearAnalysis, ...)


def find_analysis(spec: str, library: Library) -> Resolved:
    """`path/File.dyad:Name`, `path/File.dyad` (its one non-partial analysis) or `Pkg.Name`."""
    file_part, name = split_file_spec(spec)
    if file_part.endswith(".dyad"):
        parsed, package = parse_spec_file(file_part, library)
        analyses = [d for d in parsed.definitions if isinstance(d, ast.AnalysisDef)]
        chosen = [d for d in analyses if d.name == name] if name else \
            [d for d in analyses if not d.partial]
        if len(chosen) != 1:
            listed = ", ".join(d.name for d in analyses) or "none"
            what = f"no analysis `{name}` in {file_part}" if name else \
                f"{file_part} does not hold exactly one analysis; use `{file_part}:Name`"
            raise DyadError(what, parsed.span, hint=f"analyses in the file: {listed}")
        return Resolved(qualify(package, chosen[0].name), chosen[0], package, parsed)
    found = library.find(spec)
    if found is None:
        raise DyadError(f"no analysis `{spec}` on the library path",
                        hint="name it as FILE.dyad:Name or by its qualified name, with -L DIR for "
                             "its library")
    if not isinstance(found.definition, ast.AnalysisDef):
        raise DyadError(f"`{spec}` is not an analysis", found.definition.span,
                        hint=f"to simulate a component: dyadc simulate {spec} --stop T")
    return found


def read_transient(resolved: Resolved, library: Library,
                   overrides: Mapping[str, float] | None = None) -> TransientRun:
    """The run an analysis describes; `overrides` replace analysis parameters (`-p k=2`)."""
    definition = resolved.definition
    if definition.partial:
        raise DyadError(f"analysis `{definition.name}` is partial: it is a base for other "
                        f"analyses, not a run", definition.span)
    collected = collect_analysis(resolved, library, ())
    if collected.kind != TRANSIENT:
        raise DyadError(f"analysis `{definition.name}` is a `{collected.kind}`: dyadc runs "
                        f"`{TRANSIENT}` analyses only (and analyses that extend one)",
                        definition.span,
                        hint="simulate its model over time instead: an analysis that `extends "
                             "TransientAnalysis(stop = ...)` with the same `model = ...`")
    values = dict(collected.values)
    for name, value in (overrides or {}).items():
        if name not in collected.parameters and name not in FIELDS:
            continue                                   # a model parameter: the caller's business
        values[name] = ast.Number(value)
    unknown = sorted(set(values) - FIELDS - collected.parameters)
    if unknown:
        raise DyadError(f"`{TRANSIENT}` has no field `{unknown[0]}`", collected.spans.get(unknown[0])
                        or definition.span, hint=suggest_name(unknown[0], sorted(FIELDS)))
    scope = {name: value for name, value in values.items() if value is not None}
    evaluated = AnalysisValues(definition.name, scope,
                               Lexical(library, resolved.package, resolved.file))

    def field_number(name: str, default: float | None) -> float:
        if name not in scope:
            if default is None:
                raise DyadError(f"analysis `{definition.name}` gives no stop time", definition.span,
                                hint=f"extends {TRANSIENT}(stop = 10)")
            return default
        return evaluated.number(name, f"`{name}` of analysis `{definition.name}`",
                                collected.spans.get(name) or definition.span)

    stop = field_number("stop", None)
    numbers = {name: field_number(name, default) for name, default in NUMERIC_FIELDS.items()}
    _check_numbers(definition, stop, numbers, collected.spans)
    model, model_name = analysis_model(resolved, collected, scope)
    notes = []
    if "alg" in scope and text(scope["alg"]).lower() not in ("auto", "odealg.auto()"):
        notes.append(f"alg = {text(scope['alg'])} is ignored: dyadc integrates with IDAS "
                     f"(variable-order BDF)")
    if isinstance(scope.get("tstops"), ast.ArrayLit) and scope["tstops"].elements:
        notes.append("tstops are ignored: dyadc locates events itself")
    return TransientRun(resolved.qualified_name, model, model_name, stop, numbers["start"],
                        numbers["abstol"], numbers["reltol"], numbers["saveat"], numbers["dtmax"],
                        tuple(notes), definition.span, frozenset(collected.parameters))


def collect_analysis(resolved: Resolved, library: Library, seen: tuple[str, ...]) -> CollectedAnalysis:
    definition: ast.AnalysisDef = resolved.definition
    if len(definition.extends) != 1:
        raise DyadError(f"analysis `{definition.name}` must extend exactly one analysis, e.g. "
                        f"`extends {TRANSIENT}(stop = 10)`", definition.span)
    (base,) = definition.extends
    base_name = base.type_name.rsplit(".", 1)[-1]
    if base.type_name in (TRANSIENT, f"Dyad.{TRANSIENT}"):
        collected = CollectedAnalysis(kind=TRANSIENT)
    else:
        found = library.lookup(base.type_name, resolved.package, resolved.file)
        if found is None or not isinstance(found.definition, ast.AnalysisDef) \
                or found.qualified_name in seen:
            collected = CollectedAnalysis(kind=base_name, root=base_name)  # Dyad's own, or a cycle
        else:
            collected = collect_analysis(found, library, seen + (resolved.qualified_name,))
            if collected.kind != TRANSIENT:
                collected.kind = base_name             # name the kind the user wrote
    for mod in base.modifications:
        collected.values[mod.name] = mod.value
        collected.spans[mod.name] = mod.span or base.span
    for decl in definition.declarations:
        if decl.name == "model":
            collected.model = decl
        elif isinstance(decl, ast.ParameterDecl):
            collected.parameters.add(decl.name)
            collected.values[decl.name] = decl.default
            collected.spans[decl.name] = decl.span
    return collected


def analysis_model(resolved: Resolved, collected: CollectedAnalysis, scope: dict[str, Any]) -> tuple[Resolved, str]:
    """A component `extends Model(modifiers)` in the analysis's file: the model the run flattens."""
    definition = resolved.definition
    decl = collected.model
    if isinstance(decl, ast.ComponentDecl):
        type_name, mods, span = decl.type_name, decl.modifications, decl.span
    elif isinstance(decl, ast.TypedDecl) and isinstance(decl.value, ast.Call):
        call = decl.value
        if call.args:
            raise DyadError("the model of an analysis takes named modifiers only: `M(k = 2)`",
                            call.span or decl.span)
        type_name, span = call.function, decl.span
        mods = tuple(ast.Modification(k.name, k.value, span=k.span) for k in call.kwargs)
    elif isinstance(decl, ast.TypedDecl):
        type_name, mods, span = decl.type.name, decl.type.modifications, decl.span
    else:
        raise DyadError(f"analysis `{definition.name}` names no model", definition.span,
                        hint="add `model = MyComponent()`")
    if type_name.rsplit(".", 1)[-1] == "EmptyComponent":
        raise DyadError(f"analysis `{definition.name}` names no model (its model is the empty "
                        f"component)", span or definition.span, hint="add `model = MyComponent()`")
    mods = tuple(substitute(m, scope) for m in mods)
    runnable = ast.ComponentDef(definition.name, extends=(ast.Extends(type_name, mods, span=span),),
                                doc=definition.doc, span=definition.span)
    return Resolved(resolved.qualified_name, runnable, resolved.package, resolved.file), type_name


def _check_numbers(definition: ast.AnalysisDef, stop: float, numbers: dict[str, float],
                   spans: dict[str, Span | None]) -> None:
    import math

    def fail(name: str, message: str) -> None:
        raise DyadError(f"`{name}` of analysis `{definition.name}` {message}",
                        spans.get(name) or definition.span)

    for name, value in [("stop", stop), *numbers.items()]:
        if not math.isfinite(value):
            fail(name, f"must be finite, got {value}")
    if not stop > numbers["start"]:
        fail("stop", f"({stop:g}) must be after start ({numbers['start']:g})")
    for name in ("abstol", "reltol"):
        if not numbers[name] > 0:
            fail(name, f"must be positive, got {numbers[name]:g}")
    for name in ("saveat", "dtmax"):
        if numbers[name] < 0:
            fail(name, f"must not be negative, got {numbers[name]:g}")
