"""Flattening: the instance tree -> FlatSystem (scalar variables, parameters, sympy residuals).

Public API (used by the CLI): flatten_model, check_balance, summarize, format_flat,
check_library. See docs/flattening.md for the semantic choices. The pieces: flatten_state.py
(what is gathered), flatten_relations.py, flatten_variables.py, flatten_parameters.py,
flatten_connect.py and flatten_checks.py (connection sets and their checks),
flatten_metadata.py.
"""
from __future__ import annotations

from typing import Sequence

from compiler.errors import DyadError
from compiler.model.balance import check_balance, component_balance  # noqa: F401  (public API)
from compiler.model.flat import FlatSystem
from compiler.model.flatten_checks import check_inputs, unconnected_flows
from compiler.model.flatten_connect import connection_equations
from compiler.model.flatten_metadata import metadata
from compiler.model.flatten_parameters import flat_parameters
from compiler.model.flatten_relations import relation_equations
from compiler.model.flatten_report import format_flat, summarize  # noqa: F401  (public API)
from compiler.model.flatten_state import FlattenState
from compiler.model.flatten_variables import flat_variables, variable_equations
from compiler.model.instances import instance_notes
from compiler.model.instantiate import Model, instantiate
from compiler.model.library import Library, Resolved  # noqa: F401
from compiler.model.model_spec import definitions_under, load_model, resolve_model  # noqa: F401
from compiler.model.collection import fewer_collections
from compiler.syntax import ast


def flatten_model(spec: str, lib_dirs: Sequence[str] = ()) -> FlatSystem:
    """Flatten the component named by `spec` (a .dyad path, `path.dyad:Name` or a qualified
    name on the library path)."""
    library = Library(lib_dirs)
    return flatten_resolved(resolve_model(spec, library), library)


@fewer_collections()
def flatten_resolved(resolved: Resolved, library: Library) -> FlatSystem:
    from compiler.units.mode import checked      # units of the instance tree (compiler/units/)
    model = instantiate(resolved, library)
    flat = Flattener(model).run()
    flat.unit_findings = checked(model)
    return flat


class Flattener:
    """Flattens one instantiated model (`Flattener(model).run()`)."""

    def __init__(self, model: Model):
        self.model = model

    def run(self) -> FlatSystem:
        state = FlattenState(self.model)
        nodes = list(state.root.walk())
        visual_nodes = {n.path for n in nodes if n.kind == "component" and n is not state.root
                        and self.model.is_visual_only(n.resolved)}
        for node in nodes:
            if node.path in visual_nodes:
                continue
            try:
                for variable in node.variables.values():
                    variable_equations(state, variable)
                for relation, scope in node.relations:
                    relation_equations(state, relation, scope)
            except DyadError as err:
                err.notes.extend(instance_notes(node))
                raise
        connect_equations, driven = connection_equations(state.graph)
        state.equations.extend(connect_equations)
        unconnected_flows(state, nodes)
        check_inputs(state, nodes, driven)
        variables = flat_variables(state, nodes)
        parameters = flat_parameters(state, nodes, visual_nodes)
        return FlatSystem(
            name=state.root.qualified_name, variables=variables, parameters=parameters,
            equations=state.equations, initial_equations=state.initial,
            derivatives=dict(sorted(self.model.derivatives.items())), guesses=state.guesses,
            metadata=metadata(state, nodes, visual_nodes), visual=state.visual,
            warnings=state.warnings)


def check_library(root_dir: str) -> list[str]:
    """Check every non-partial component under `root_dir` as `dyadc check` does; one line per
    component: `ok: Name (E equations, U unknowns)`, `partial: Name: balanced as a component,
    N open connectors (...)` for a component that cannot run alone, or the rendered error."""
    from compiler.model.model_check import check_model
    from pathlib import Path
    library = Library([root_dir])
    unparsed: list[DyadError] = []          # every file that does not parse is reported
    definitions = definitions_under(library, Path(root_dir), unparsed)
    lines = [err.format() for err in unparsed]
    for resolved in definitions:
        definition = resolved.definition
        if not isinstance(definition, ast.ComponentDef) or definition.partial:
            continue
        try:
            flat = flatten_resolved(resolved, library)
            verdict = check_model(flat)
        except DyadError as err:
            lines.append(f"{resolved.qualified_name}: {err.format()}")
            continue
        if verdict.is_partial:
            lines.append(f"partial: {resolved.qualified_name}: "
                         f"{verdict.describe().removeprefix('partial: ')}")
            continue
        lines.append(f"ok: {resolved.qualified_name} ({verdict.equations} equations, "
                     f"{verdict.unknowns} unknowns)")
    return lines
