"""A test case's `"initial"` map applied to a flat model, the way Dyad's `u0` map is applied.

For an unknown `x`, `"initial": {"x": 10}` is the initial condition x(t0) = 10: it replaces an
initial equation the model itself writes for `x` alone (`initial x = 0`, or an `initial` modifier),
and becomes the variable's start value (the first iterate of the initialization and the size that
scales its absolute tolerance). For a parameter it is the parameter's value for that run. The
flat model is not changed: a new FlatSystem is returned.
"""
from __future__ import annotations

import dataclasses
from typing import Mapping

import sympy

from compiler.errors import DyadError, Span, suggest_name
from compiler.model.flat import Equation, FlatSystem, Origin


def with_start_values(flat: FlatSystem, values: Mapping[str, float], where: str,
                      span: Span | None) -> tuple[FlatSystem, dict[str, float]]:
    """(the flat model with the unknowns' initial conditions, the parameter values to pass to
    the run). A name that is neither an unknown nor a parameter is an error located at `span`."""
    unknowns = {v.name for v in flat.variables}
    parameters = {p.name for p in flat.parameters}
    fixed: dict[str, float] = {}
    params: dict[str, float] = {}
    for name, value in values.items():
        if name in unknowns:
            fixed[name] = float(value)
        elif name in parameters:
            params[name] = float(value)
        else:
            raise DyadError(f'{where}: "initial" names `{name}`, which is neither a variable nor a '
                            f"parameter of {flat.name}", span,
                            hint=suggest_name(name, sorted(unknowns | parameters)))
    if not fixed:
        return flat, params
    unknown_symbols = {sympy.Symbol(n) for n in unknowns} | {sympy.Symbol(d) for d in flat.derivatives}
    kept = [eq for eq in flat.initial_equations
            if _fixes_alone(eq.residual, unknown_symbols) not in fixed]
    origin = Origin("", span)
    added = [Equation(sympy.Symbol(name) - sympy.Float(value), origin, "equation",
                      f"{where}: initial value") for name, value in fixed.items()]
    variables = [dataclasses.replace(v, start=fixed[v.name]) if v.name in fixed else v
                 for v in flat.variables]
    return dataclasses.replace(flat, variables=variables, initial_equations=kept + added), params


def _fixes_alone(residual: sympy.Expr, unknowns: set[sympy.Symbol]) -> str | None:
    """The name of x when `residual` is ±(x - c) with c free of unknowns, else None."""
    involved = residual.free_symbols & unknowns
    if len(involved) != 1:
        return None
    (symbol,) = involved
    for sign in (1, -1):
        rest = sympy.expand(sign * residual - symbol)
        if symbol not in rest.free_symbols:
            return symbol.name
    return None
