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

Here: how the verdict is reached; verdict.py: what it says (`check`'s line, `simulate`'s error);
parameter_checks.py: the values a run needs.
"""
from __future__ import annotations

from dataclasses import replace

from compiler.model.balance import check_balance, incidence, span_from_text, unbalanced_components, \
    unknown_names
from compiler.errors import DyadError, Note
from compiler.model.flat import INPUT, FlatSystem
from compiler.model.floating import FloatingCluster, floating_clusters
from compiler.model.parameter_checks import require_parameter_values, used_parameter_names
from compiler.model.verdict import Verdict
from compiler.julia.objects import opaque_calls
from compiler.structure.graph.dulmage_mendelsohn import dulmage_mendelsohn


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
