"""Connection checks of flattening: a flow of a connector nobody connects is zero, and an input
of a subcomponent must be driven by a connection or by an equation written outside it."""
from __future__ import annotations

from compiler.errors import DyadError, Note
from compiler.model.flat import Equation, Origin
from compiler.model.flatten_state import FlattenState, owner_of, scalars
from compiler.model.instantiate import Instance


def unconnected_flows(state: FlattenState, nodes: list[Instance]) -> None:
    for node in nodes:
        if node.kind != "connector" or state.graph.is_inside_connected(node.path):
            continue
        owner = node.parent
        where = owner.parent.path if owner is not None and owner.parent is not None else ""
        for variable in node.variables.values():
            if variable.connector_kind == "flow":
                for sym in scalars(variable.symbols):
                    state.equations.append(Equation(sym, Origin(where, node.decl_span),
                                                   "unconnected_flow"))


def check_inputs(state: FlattenState, nodes: list[Instance], driven: dict[str, bool]) -> None:
    """An input of a subcomponent must be driven by a connection or given by an equation
    written outside that subcomponent (e.g. `controller.s_ref = s_ref`)."""
    used_outside: dict[str, set[str]] | None = None
    for node in nodes:
        for variable in node.variables.values():
            if variable.causality != "input":
                continue
            owner = owner_of(variable)
            undriven = [name for name in variable.names if not driven.get(name)]
            if owner is state.root or driven.get(variable.path) or not undriven:
                continue
            if used_outside is None:
                used_outside = _symbol_origins(state)
            origins = set()
            for name in undriven:
                origins |= used_outside.get(name, set())
            if any(not _inside(path, owner.path) for path in origins):
                continue
            # an array some of whose elements are connected: name the first element left over
            path = undriven[0] if len(undriven) < len(variable.names) else variable.path
            raise DyadError(
                f"input `{path}` is not connected and no equation gives it a value",
                owner.decl_span,
                hint=f"connect it to an output, or write `{path} = ...` in the "
                     f"enclosing component",
                notes=[Note(f"`{variable.name}` is declared here", variable.span)])


def _symbol_origins(state: FlattenState) -> dict[str, set[str]]:
    out: dict[str, set[str]] = {}
    for equation in state.equations:
        for sym in equation.residual.free_symbols:
            out.setdefault(sym.name, set()).add(equation.origin.path)
    return out


def _inside(path: str, ancestor: str) -> bool:
    return path == ancestor or path.startswith(ancestor + ".")
