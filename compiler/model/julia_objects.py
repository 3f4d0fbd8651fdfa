"""Calls that pass a Julia object (a `path` connector field: a fluid medium) to a function.

Dyad carries a medium along a connected path (`path medium::AbstractMedium` in a connector) and
its libraries compute with it in Julia: `rho = density(port.medium, p)`, where Julia picks the
method of `density` by the medium's type. dyadc cannot evaluate such a call, but the call's
structure is plain: one value that depends on its numeric arguments. So the call becomes an
opaque function of those arguments (`density(p)`), which is enough for balance, matching and
`dyadc check`; a run refuses the model with the call named (`opaque_calls`,
compiler/model/model_check.py).
"""
from __future__ import annotations

from typing import Any

import sympy
from sympy.core.function import AppliedUndef, UndefinedFunction

from compiler.syntax import ast


class OpaqueJuliaCall(AppliedUndef):
    """An applied function of a Julia object whose value dyadc cannot compute."""


def path_field_of(ref: ast.Expr, node: Any) -> str | None:
    """The dotted name of the `path` field that `ref` reads from `node` (e.g. `port.medium`),
    else None. Only walks through subcomponents and connectors; never evaluates anything."""
    if not isinstance(ref, ast.Ref) or any(part.indices for part in ref.parts):
        return None
    for part in ref.parts[:-1]:
        node = getattr(node, "children", {}).get(part.name)
        if node is None or not hasattr(node, "path_fields"):
            return None
    return ref.dotted if ref.parts[-1].name in getattr(node, "path_fields", {}) else None


def opaque_call(name: str, package: str, call: ast.Call, node: Any, evaluate_argument) -> Any:
    """The call as an opaque function of its numeric arguments when some argument is a `path`
    field, else None (an ordinary call). `evaluate_argument(expr)` gives an argument's value."""
    objects = [path_field_of(arg, node) for arg in call.args]
    if not any(objects) or call.kwargs:
        return None
    qualified = name if "." in name or not package else f"{package}.{name}"
    numeric = [evaluate_argument(arg) for arg, obj in zip(call.args, objects) if obj is None]
    function = UndefinedFunction(qualified, bases=(OpaqueJuliaCall,))
    return function(*numeric)


def opaque_calls(expressions) -> list[str]:
    """Names of the opaque calls in some sympy expressions, sorted, each once."""
    found: set[str] = set()
    for expr in expressions:
        if isinstance(expr, sympy.Basic) and expr.has(OpaqueJuliaCall):
            found.update(type(call).__name__ for call in expr.atoms(OpaqueJuliaCall))
    return sorted(found)
