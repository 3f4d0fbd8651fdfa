"""Flattening a variable: its binding and `initial` value as equations, its guess, start,
state priority, units and bounds, and its kind in the flat system (state candidate, input,
output or algebraic)."""
from __future__ import annotations

from typing import Any

import sympy

from compiler.errors import DyadError, Span
from compiler.model.expressions import EvalScope, MissingValue, Mode, evaluate, numeric, shape_of, \
    structural_int
from compiler.model.flat import ALGEBRAIC, INPUT, OUTPUT, STATE_CANDIDATE, Equation, Origin, Variable
from compiler.model.flatten_state import FlattenState, owner_of, scalars, to_float
from compiler.model.instantiate import Instance, VariableInstance
from compiler.syntax import ast


def variable_equations(state: FlattenState, variable: VariableInstance) -> None:
    if variable.binding is not None:
        expr, scope, span = variable.binding
        value = numeric(evaluate(expr, scope, Mode.SYMBOLIC), span)
        bind(variable, value, Origin(scope.node.path, span), span, "binding",
                   state.equations)
    attributes = variable.attributes
    if "initial" in attributes:
        expr, scope = attributes["initial"]
        span = getattr(expr, "span", None) or variable.span
        value = numeric(evaluate(expr, scope, Mode.SYMBOLIC), span)
        bind(variable, value, Origin(scope.node.path, span), span, "equation",
                   state.initial)
        for name, number in zip(variable.names, broadcast(variable, value, span)):
            start = state.numeric_or_none(number)
            if start is not None:
                state.starts[name] = start
    for attribute in ("guess", "start"):
        if attribute in attributes:
            expr, scope = attributes[attribute]
            set_numeric_attribute(state, state.guesses, variable.symbols, expr, scope,
                                        getattr(expr, "span", None) or variable.span, attribute)
    if "state_priority" in attributes:
        expr, scope = attributes["state_priority"]
        priority = structural_int(evaluate(expr, scope, Mode.STRUCTURAL), expr.span,
                                  "state_priority")
        for name in variable.names:
            state.priorities[name] = priority
    if "units" in attributes:
        expr, scope = attributes["units"]
        units = evaluate(expr, scope, Mode.NUMERIC)
        if getattr(units, "is_number", False) and units == 1:
            units = "1"         # Dyad writes a dimensionless unit as the number `units = 1`
        if not isinstance(units, str):
            raise DyadError("`units` must be a string", expr.span)
        for name in variable.names:
            state.units[name] = units
    for bound in ("min", "max"):
        if bound in attributes:
            expr, scope = attributes[bound]
            store: dict[str, float] = {}
            set_numeric_attribute(state, store, variable.symbols, expr, scope, expr.span, bound)
            for name, number in store.items():
                state.bounds.setdefault(name, {})[bound] = number


def set_numeric_attribute(state: FlattenState, store: dict, target: Any, expr: ast.Expr,
                          scope: EvalScope, span: Span | None, what: str) -> None:
    try:
        value = numeric(evaluate(expr, scope, Mode.NUMERIC), span)
    except MissingValue as missing:
        state.warnings.append(f"{span}: {what} ignored: parameter `{missing.name}` has no value")
        return
    symbols = scalars(target)
    values = scalars(value)
    if len(values) == 1 and len(symbols) > 1:
        values = values * len(symbols)
    if len(values) != len(symbols):
        raise DyadError(f"array size mismatch: the {what} has size {shape_of(value) or 'scalar'}"
                        f" but the variable has size {shape_of(target) or 'scalar'}", span)
    for sym, number in zip(symbols, values):
        if not isinstance(sym, sympy.Symbol) or not state.model.is_unknown(sym.name):
            raise DyadError(f"a {what} can only be given for a variable", span)
        as_float = to_float(number)
        if as_float is None:
            raise DyadError(f"the {what} must be a number", span)
        store[sym.name] = as_float


def broadcast(variable: VariableInstance, value: Any, span: Span | None) -> list[Any]:
    values = scalars(value)
    if len(values) == 1 and len(variable.names) > 1:
        values = values * len(variable.names)
    if len(values) != len(variable.names):
        raise DyadError(f"array size mismatch: `{variable.path}` has size "
                        f"{variable.shape or 'scalar'} but the value has size "
                        f"{shape_of(value) or 'scalar'}", span)
    return values


def bind(variable: VariableInstance, value: Any, origin: Origin, span: Span | None, kind: str,
         target: list[Equation]) -> None:
    for sym, number in zip(scalars(variable.symbols), broadcast(variable, value, span)):
        target.append(Equation(sym - number, origin, kind))


def flat_variables(state: FlattenState, nodes: list[Instance]) -> list[Variable]:
    out: list[Variable] = []
    for node in nodes:
        for variable in node.variables.values():
            owner = owner_of(variable)
            top_signal = owner is state.root and variable.is_signal
            for name in variable.names:
                if top_signal and variable.causality == "input":
                    kind = INPUT
                elif name in state.model.differentiated:
                    kind = STATE_CANDIDATE
                elif top_signal:
                    kind = OUTPUT
                else:
                    kind = ALGEBRAIC
                out.append(Variable(
                    name=name, kind=kind,
                    units=state.units.get(name) or _type_units(variable),
                    start=state.starts.get(name), guess=state.guesses.get(name),
                    state_priority=state.priorities.get(name, 0), description=variable.doc,
                    origin=Origin(owner.path, variable.span)))
    return out


def _type_units(variable: VariableInstance) -> str | None:
    for mod, _ in reversed(variable.type.attributes):
        if mod.name == "units" and isinstance(mod.value, ast.String):
            return mod.value.value
    return None
