"""Flattening parameters: scalar flat parameters with value, symbolic default and tunability;
string parameters kept aside; parameters of visual-only components kept with the scene unless
an equation refers to them."""
from __future__ import annotations

from typing import Any

from compiler.model.expressions import Mode, evaluate, is_array
from compiler.model.flat import Origin, Parameter
from compiler.model.flatten_state import FlattenState, scalars, to_float
from compiler.model.instantiate import Instance, ParameterInstance
from compiler.model.symbols import free_symbols


def plain(value: Any) -> Any:
    """A parameter value as plain Python data (floats, lists, str) for visual/metadata."""
    if is_array(value):
        return [plain(v) for v in value]
    if isinstance(value, str) or value is None:
        return value
    return to_float(value)


def flat_parameters(state: FlattenState, nodes: list[Instance],
                    visual_nodes: set[str]) -> list[Parameter]:
    out: list[Parameter] = []
    pending_visual: list[ParameterInstance] = []
    strings: dict[str, str] = {}
    for node in nodes:
        if node.path in visual_nodes:
            state.visual[node.path] = {
                "type": node.qualified_name,
                "parameters": {p.name: _visual_value(p) for p in node.parameters.values()},
            }
            continue
        for parameter in node.parameters.values():
            if parameter.is_string:
                strings[parameter.path] = parameter.value()
                continue
            owner = state.model.library.find(parameter.owner)
            if owner is not None and state.model.is_visual_only(owner):
                pending_visual.append(parameter)
                continue
            out.extend(_flat_parameters(state, parameter))
    if pending_visual:
        referenced = _referenced_parameters(state, out)
        for parameter in pending_visual:
            if any(name in referenced for name in parameter.flat_names()):
                out.extend(_flat_parameters(state, parameter))
            else:
                entry = state.visual.setdefault(parameter.node.path, {
                    "type": parameter.node.qualified_name, "parameters": {}})
                entry["parameters"][parameter.name] = _visual_value(parameter)
    state.strings = strings
    return out


def _visual_value(parameter: ParameterInstance) -> Any:
    value = plain(parameter.value())
    if parameter.type.primitive == "Boolean" and isinstance(value, float):
        return bool(value)
    return value


def _flat_parameters(state: FlattenState, parameter: ParameterInstance) -> list[Parameter]:
    value = parameter.value()
    if value is None and parameter.binding is None:
        state.warnings.append(f"{parameter.span}: parameter `{parameter.path}` has no value: "
                             f"give one when simulating (-p {parameter.path}=VALUE)")
    default = parameter.symbolic_default()
    values = scalars(value) if value is not None else [None] * len(parameter.flat_names())
    defaults = scalars(default) if default is not None else [None] * len(values)
    tunable = not (parameter.final or parameter.fixed_at_compile_time
                   or parameter.structural_use)
    units_attr = parameter.attributes.get("units")
    units = None
    if units_attr is not None:
        units = evaluate(units_attr[0], units_attr[1], Mode.NUMERIC)
    return [Parameter(name=name, value=to_float(v) if v is not None else None, default=d,
                      tunable=tunable, variability=parameter.variability,
                      units=units if isinstance(units, str) else None,
                      description=parameter.decl.doc,
                      origin=Origin(parameter.node.path, parameter.span),
                      type_name=parameter.decl.type.name,
                      instance_span=parameter.node.decl_span if parameter.node.parent else None)
            for name, v, d in zip(parameter.flat_names(), values, defaults)]


def _referenced_parameters(state: FlattenState, parameters: list[Parameter]) -> set[str]:
    referenced: set[str] = set()
    for equation in state.equations + state.initial:
        referenced.update(s.name for s in free_symbols(equation.residual))   # memoized: alias reuses it
    defaults = {p.name: p.default for p in parameters}
    stack = [name for name in referenced if name in defaults]
    while stack:
        default = defaults.get(stack.pop())
        for sym in getattr(default, "free_symbols", ()):
            if sym.name not in referenced:
                referenced.add(sym.name)
                stack.append(sym.name)
    return referenced
