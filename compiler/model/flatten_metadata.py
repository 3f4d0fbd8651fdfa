"""The metadata of a flat system: component and connector summaries for the model checks,
instance metadata, bounds, strings and analysis points."""
from __future__ import annotations

from compiler.errors import Span
from compiler.model.flatten_state import FlattenState
from compiler.model.instantiate import Instance
from compiler.syntax import ast


def span_text(span: Span | None) -> str | None:
    return f"{span.file}:{span.line}:{span.column}" if span else None


def metadata(state: FlattenState, nodes: list[Instance], visual_nodes: set[str]) -> dict:
    components: dict[str, dict] = {}
    connectors: dict[str, dict] = {}
    instance_metadata: dict[str, dict] = {}
    for node in nodes:
        meta = ast.metadata_dict(getattr(node.resolved.definition, "metadata", None))
        if meta:
            instance_metadata[node.path] = meta
        if node.kind == "connector" and node.parent is not None \
                and node.parent.path not in visual_nodes:
            connectors[node.path] = _connector_info(state, node)
        if node.kind != "component" or node.path in visual_nodes:
            continue
        flows: list[str] = []
        inputs: list[str] = []
        for child in node.child_instances():
            if child.kind == "connector":
                for variable in child.variables.values():
                    if variable.connector_kind == "flow":
                        flows.extend(variable.names)
                    elif variable.causality == "input":
                        inputs.extend(variable.names)
        for variable in node.variables.values():
            if variable.causality == "input":
                inputs.extend(variable.names)
        components[node.path] = {"type": node.qualified_name, "span": span_text(node.decl_span),
                                 "connector_flows": flows, "inputs": inputs}
    top = instance_metadata.get("", {})
    return {"Dyad": top.get("Dyad", {}), "instances": instance_metadata,
            "components": components, "connectors": connectors, "bounds": state.bounds,
            "declared_partial": bool(getattr(state.root.resolved.definition, "partial", False)),
            "declared_external": bool(getattr(state.root.resolved.definition, "external", False)),
            "strings": state.strings,
            "analysis_points": state.graph.analysis_points,
            "model_span": span_text(state.root.resolved.definition.span)}


def _connector_info(state: FlattenState, node: Instance) -> dict:
    """What the model checks need about a physical connector instance: its type, owner,
    scalar potential and flow names per field, and whether any `connect` names it."""
    fields: dict[str, dict[str, list[str]]] = {"potential": {}, "flow": {}}
    for variable in node.variables.values():
        if variable.connector_kind in fields:
            fields[variable.connector_kind][variable.name] = list(variable.names)
    return {"type": node.resolved.name, "owner": node.parent.path,
            "span": span_text(node.decl_span), "connected": state.graph.is_connected(node.path),
            "potentials": fields["potential"], "flows": fields["flow"]}
