"""Can a flat model be simulated on its own? The one set of checks behind both `dyadc check` and
`simulate` (compiler/pipeline.py), so that the two never disagree.

The checks, on the model closed as it stands (top-level inputs are unknowns nobody drives, the
flows of top-level connectors are zero): balance, globally and per component instance; a complete
matching of equations to unknowns; connector sets whose potentials float (no ground / fixed
reference, compiler/model/floating.py).

A model that fails them may still be a good component: a `Resistor` with open pins, a `Gain`
with an open input, a base declared `partial`. Such a model is *partial*: `dyadc check` says so
("partial: balanced as a component, 2 open connectors (p, n)") and `simulate` refuses it with the
open connectors named. Balanced as a component means Modelica's rule: its equations, without the
zero flows of its own open connectors, equal its unknowns minus those flows and its inputs.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

from compiler.model.balance import check_balance, incidence, span_from_text, unbalanced_components, \
    unknown_names
from compiler.errors import DyadError, Note
from compiler.model.flat import INPUT, FlatSystem
from compiler.model.floating import FloatingCluster, floating_clusters
from compiler.julia.objects import opaque_calls
from compiler.structure.graph.dulmage_mendelsohn import dulmage_mendelsohn


@dataclass(frozen=True)
class Verdict:
    model: str
    equations: int
    unknowns: int
    open_connectors: tuple[str, ...] = ()     # physical connectors of the model itself
    open_inputs: tuple[str, ...] = ()         # its input signals
    declared_partial: bool = False
    component_equations: int = 0              # without the zero flows of its open connectors
    component_unknowns: int = 0               # without those flows and its inputs
    reason: DyadError | None = None           # why it cannot run on its own (None: it can)
    declared_external: bool = False           # `external component`: equations written in Julia
    julia_object_calls: tuple[str, ...] = ()  # functions of a medium (compiler/julia/objects.py)
    julia_object_span: object = None          # the first equation that calls one

    @property
    def is_partial(self) -> bool:
        return self.reason is not None

    @property
    def open_count(self) -> int:
        return len(self.open_connectors) + len(self.open_inputs)

    def open_list(self) -> str:
        return ", ".join(self.open_connectors + self.open_inputs)

    def describe(self) -> str:
        """One status line for `dyadc check`."""
        if not self.is_partial:
            return f"balanced: {self.equations} equations, {self.unknowns} unknowns" \
                + self._julia_object_note()
        opened = (f"{self.open_count} open connector{'s' if self.open_count != 1 else ''}"
                  + (f" ({self.open_list()})" if self.open_count else ""))
        if self.declared_external:
            return (f"external: interface only, {self.unknowns} unknowns and {opened}; its "
                    f"equations are implemented in Julia, so dyadc cannot simulate it")
        if self.component_equations == self.component_unknowns:
            state = "balanced as a component"
        else:
            state = (f"{self.component_equations} equations for {self.component_unknowns} unknowns "
                     f"as a component")
        declared = "declared partial, " if self.declared_partial else ""
        return f"partial: {declared}{state}, {opened}; it cannot be simulated on its own" \
            + self._julia_object_note()

    def _julia_object_note(self) -> str:
        if not self.julia_object_calls:
            return ""
        return (f"; dyadc cannot simulate it: {_calls(self.julia_object_calls)} of a Julia "
                f"object (a medium, a dataset, an interpolator), kept opaque for these checks")

    def julia_object_error(self) -> DyadError:
        return DyadError(f"`{self.model}` cannot be simulated by dyadc: it calls "
                         f"{_calls(self.julia_object_calls)} with a Julia object (a medium, a "
                         f"dataset, an interpolator) whose value dyadc cannot represent",
                         self.julia_object_span,
                         hint="`dyadc check` still checks its structure; a run needs Dyad's Julia "
                              "runtime, or a medium declared in the model (`path medium::M = "
                              "Struct(...)`) whose Julia struct and methods dyadc can read")

    def error(self) -> DyadError:
        """Why `simulate` refuses a partial model: what is open, and (as a note) what goes wrong
        when it is closed as it stands."""
        reason = self.reason
        opened = {1: f"its connector {self.open_list()} is left open"}.get(
            self.open_count, f"its {self.open_count} connectors {self.open_list()} are left open")
        if self.declared_external:
            return DyadError(f"`{self.model}` is an external component: its equations are "
                             f"implemented in Julia, which dyadc cannot run", reason.span,
                             hint="replace it by a component whose relations are written in Dyad")
        if self.declared_partial:
            head = f"`{self.model}` is declared partial: an incomplete component, it cannot be simulated"
            hint = "simulate a model that uses a component extending it"
        else:
            head = f"`{self.model}` is a partial model: it cannot be simulated on its own"
            hint = "simulate a model that uses it"
        if self.open_count:
            head += f"; {opened}"
            hint += f" and connects {self.open_list()}"
        if self.open_connectors:
            hint += " (e.g. to sources and a reference such as Ground or Fixed)"
        if self.open_inputs:
            hint += "; an input is driven by connecting it to an output (e.g. a Constant block)"
        notes = [Note(f"closed as it stands, {reason.message}", reason.span)]
        return DyadError(head, reason.span, hint=hint, notes=notes)


def assess(flat: FlatSystem) -> Verdict:
    """The verdict on `flat`; raises a located DyadError if the model is wrong even as a component."""
    return _with_julia_objects(flat, _assess(flat))


def _assess(flat: FlatSystem) -> Verdict:
    connectors = flat.metadata.get("connectors") or {}
    open_connectors = tuple(p for p, info in connectors.items() if info["owner"] == "")
    open_inputs = tuple(v.name for v in flat.variables if v.kind == INPUT)
    top_flows = {n for p in open_connectors for names in connectors[p]["flows"].values() for n in names}
    zero_flows = sum(1 for e in flat.equations
                     if e.kind == "unconnected_flow" and e.residual.is_Symbol and e.residual.name in top_flows)
    unknowns = len(unknown_names(flat, closed=True))
    verdict = Verdict(flat.name, len(flat.equations), unknowns, open_connectors, open_inputs,
                      declared_partial=bool(flat.metadata.get("declared_partial")),
                      component_equations=len(flat.equations) - zero_flows,
                      component_unknowns=unknowns - len(top_flows) - len(open_inputs))
    if flat.metadata.get("declared_external"):
        # its relations live in Julia: the interface instantiated, nothing more can be counted
        return replace(verdict, declared_external=True, reason=DyadError(
            f"`{flat.name}` has no relations in Dyad (external)",
            span_from_text(flat.metadata.get("model_span"))))
    try:
        check_closed(flat)
    except DyadError as err:
        balanced_as_component = verdict.component_equations == verdict.component_unknowns
        if verdict.declared_partial or (verdict.open_count and balanced_as_component):
            return replace(verdict, reason=err)
        if verdict.open_count and not unbalanced_components(flat):
            raise _component_imbalance(flat, verdict, err, top_flows) from None
        raise
    if verdict.declared_partial:
        return replace(verdict, reason=DyadError(f"`{flat.name}` is declared partial",
                                                 span_from_text(flat.metadata.get("model_span"))))
    return verdict


def check_model(flat: FlatSystem) -> Verdict:
    """`dyadc check`: the verdict of `assess`, and for a model that runs on its own, the values
    its run needs. A subcomponent's parameter without a value is an error, as in `simulate`: its
    value belongs where this model instantiates it. The checked component's own parameters may
    lack one: whoever uses the component gives it (a library part such as a gain `k`), or `-p`
    when it is simulated alone; flattening warns of them."""
    verdict = assess(flat)
    if not verdict.is_partial:
        own = {p.name for p in flat.parameters if p.origin.path == ""}
        require_parameter_values(flat, used_parameter_names(flat) - own)
    return verdict


def require_standalone(flat: FlatSystem) -> Verdict:
    """For `simulate`: a partial model is an error that names its open connectors; so is a
    model that computes with a Julia object."""
    verdict = assess(flat)
    if verdict.is_partial:
        raise verdict.error()
    if verdict.julia_object_calls:
        raise verdict.julia_object_error()
    return verdict


def _calls(names: tuple[str, ...]) -> str:
    shown = ", ".join(f"`{name}`" for name in names[:3])
    return ("function " if len(names) == 1 else "functions ") + shown \
        + (f" and {len(names) - 3} more" if len(names) > 3 else "")


def _with_julia_objects(flat: FlatSystem, verdict: Verdict) -> Verdict:
    calling = [e for e in flat.equations + flat.initial_equations if opaque_calls([e.residual])]
    if not calling:
        return verdict
    return replace(verdict, julia_object_span=calling[0].origin.span,
                   julia_object_calls=tuple(opaque_calls(e.residual for e in calling)))


def check_closed(flat: FlatSystem) -> None:
    check_balance(flat, structural=True, closed=True)
    floating = floating_clusters(flat)
    if floating:
        raise floating_error(flat, floating)


def floating_error(flat: FlatSystem, clusters: list[FloatingCluster]) -> DyadError:
    first = clusters[0]
    sets = " ".join("{" + ", ".join(group) + "}" for group in first.connect_sets)
    head = (f"nothing fixes the absolute `{first.field}` of the {first.connector_type} connector "
            f"set{'s' if len(first.connect_sets) > 1 else ''} {sets}: they float, every equation "
            f"depends only on differences of their `{first.field}`, so the model is singular")
    notes = [Note(f"the {c.connector_type} connectors "
                  + " ".join("{" + ", ".join(g) + "}" for g in c.connect_sets)
                  + f" float in `{c.field}` too", span_from_text(c.span_text)) for c in clusters[1:6]]
    return DyadError(head, span_from_text(first.span_text)
                     or span_from_text(flat.metadata.get("model_span")), notes=notes,
                     hint=f"connect one of these connectors to {first.reference()}")


def _component_imbalance(flat: FlatSystem, verdict: Verdict, closed: DyadError,
                         top_flows: set[str]) -> DyadError:
    """A model with open connectors whose own count is off: say it in a component's terms (the
    closed model's notes would blame the zero flows of its open connectors), and name the culprit
    equation set from the Dulmage-Mendelsohn partition of the component's own system."""
    given = verdict.unknowns - verdict.component_unknowns
    sources = []
    if verdict.open_connectors:
        sources.append(f"the flows of its connectors {', '.join(verdict.open_connectors)}")
    if verdict.open_inputs:
        sources.append(f"its inputs {', '.join(verdict.open_inputs)}")
    return DyadError(
        f"component `{verdict.model}` is unbalanced: {verdict.component_equations} equation(s) for "
        f"{verdict.component_unknowns} unknown(s) ({given} more, {' and '.join(sources)}, are given "
        f"by its connections)", closed.span, notes=_culprit_notes(flat, top_flows),
        hint="a component needs one equation per unknown, not counting what its connectors "
             "receive: add the missing equations or remove the extra ones")


def _culprit_notes(flat: FlatSystem, top_flows: set[str]) -> list[Note]:
    """The component's own equations plus what its environment will supply: per flow of an open
    connector one equation in that connector's variables (whatever it gets connected to relates
    them), per input one equation fixing it. The over- or under-determined part names the culprit."""
    own = [e for e in flat.equations
           if not (e.kind == "unconnected_flow" and e.residual.is_Symbol and e.residual.name in top_flows)]
    names, rows = incidence(flat, own, closed=True)
    index = {n: i for i, n in enumerate(names)}
    for info in (flat.metadata.get("connectors") or {}).values():
        if info["owner"] != "":
            continue
        members = sorted(index[n] for group in ("potentials", "flows")
                         for names_ in info[group].values() for n in names_ if n in index)
        rows += [members for names_ in info["flows"].values() for _ in names_]
    rows += [[index[v.name]] for v in flat.variables if v.kind == INPUT]
    dm = dulmage_mendelsohn(len(rows), len(names), rows)
    over = [e for e in dm.overdetermined_eqs if e < len(own)]
    notes = [Note(f"over-determined: `{own[e].residual} = 0` ({own[e].origin.path or 'the component'})",
                  own[e].origin.span) for e in over[:6]]
    if dm.underdetermined_vars:
        under = [names[v] for v in dm.underdetermined_vars]
        notes.append(Note(f"under-determined: nothing determines all of "
                          f"{', '.join(under[:8])}{' ...' if len(under) > 8 else ''}"))
    return notes


def require_tunable_overrides(flat: FlatSystem, overrides=None) -> None:
    """Before a run: an override (`-p name=VALUE`) names no parameter that is fixed when the
    model is compiled (a structural one sizes arrays and picks branches; a constant or `final`
    one is bound by its declaration)."""
    fixed = {p.name: p for p in flat.parameters if not p.tunable}
    for name in overrides or ():
        parameter = fixed.get(name)
        if parameter is None:
            continue
        local = name.rsplit(".", 1)[-1]
        if parameter.variability == "structural":
            raise DyadError(
                f"parameter `{name}` of `{flat.name}` is structural: it is fixed when the model is "
                f"compiled (array sizes, branches), so a run cannot override it", parameter.origin.span,
                hint=f"change it in the source: the value in its declaration, or a modifier where "
                     f"its component is used, e.g. `Name({local} = VALUE)`")
        what = "a constant" if parameter.variability == "constant" else "final"
        raise DyadError(f"parameter `{name}` of `{flat.name}` is {what}: its declaration binds its "
                        f"value, so a run cannot override it", parameter.origin.span,
                        hint="override the parameters its value is computed from, if any")


def require_parameter_values(flat: FlatSystem, used: set[str] | None = None, overrides=None) -> None:
    """Before a run (and in `dyadc check`, which runs without overrides): every parameter the
    equations use (`used`; default: those of `flat`'s equations) has a value, from its declaration,
    a modifier where its component is used, or the caller (`-p name=VALUE`)."""
    given = set(overrides or ())
    used = used_parameter_names(flat) if used is None else used
    missing = [p for p in flat.parameters
               if p.name in used and p.value is None and p.default is None and p.name not in given]
    if missing:
        raise missing_values_error(flat, missing)


def used_parameter_names(flat: FlatSystem) -> set[str]:
    """The parameters `flat`'s equations and initial equations use, closed over the bindings of
    other parameters."""
    by_name = {p.name: p for p in flat.parameters}
    pending = [s.name for e in flat.equations + flat.initial_equations
               for s in e.residual.free_symbols if s.name in by_name]
    used: set[str] = set()
    while pending:
        name = pending.pop()
        if name in used:
            continue
        used.add(name)
        default = by_name[name].default
        if default is not None:
            pending.extend(s.name for s in default.free_symbols if s.name in by_name)
    return used


def missing_values_error(flat: FlatSystem, missing: list) -> DyadError:
    """Parameters without a value, located at the first one's declaration, with a note at the
    place where its component is instantiated (where a value belongs) and a hint in its own type."""
    first = missing[0]
    names = ", ".join(f"`{p.name}`" for p in missing)
    example = " ".join(f"-p {p.name}=VALUE" for p in missing[:3])
    local = first.name.rsplit(".", 1)[-1]
    notes = [Note(f"`{p.name}` is declared here without a value", p.origin.span) for p in missing[1:8]]
    where = f"`parameter {local}::{first.type_name} = VALUE` in the declaration"
    if first.instance_span is not None:
        instance = first.origin.path.rsplit(".", 1)[-1]
        notes.insert(0, Note(f"`{instance}` is instantiated here: give `{local}` a value in its "
                             f"modifiers, e.g. `{local} = VALUE`", first.instance_span))
        where = f"a modifier where `{instance}` is instantiated (`{local} = VALUE`, see the note)"
    return DyadError(
        f"parameter{'s' if len(missing) > 1 else ''} {names} of `{flat.name}` "
        f"{'have' if len(missing) > 1 else 'has'} no value", first.origin.span, notes=notes,
        hint=f"give a value in {where}, or when simulating (`dyadc simulate ... {example}`, or "
             f"params={{'{first.name}': VALUE}} from Python)")
