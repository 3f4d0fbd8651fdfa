"""Calls that pass a Julia object (a `path` connector field: a fluid medium) to a function.

Dyad carries a medium along a connected path (`path medium::AbstractMedium` in a connector) and
its libraries compute with it in Julia: `rho = density(port.medium, p)`, where Julia picks the
method of `density` by the medium's type. The medium itself is declared once, in the model that
closes the path, and joined to a port with `continuity`:

    path medium::AbstractMedium = Oil(bulk_modulus = 1e9)
    continuity(medium, tank.port.medium)

When the path holds such a declaration and the medium is a Julia struct of the package
(compiler/julia/methods.py), the call is evaluated: the method typed with the struct (or
its supertype) is inlined with the medium's field values (`@unpack` in its body). Otherwise (a
component checked alone, with its ports open) the call becomes an opaque function of its numeric
arguments: enough for balance, matching and `dyadc check`, while a run refuses the model with
the call named (`opaque_calls`, compiler/model/model_check.py).

The model's evaluator reaches `medium_call` through its registry of object calls
(compiler/model/object_calls.py) and hands it an `Evaluator`; nothing here imports
compiler.model.
"""
from __future__ import annotations

from dataclasses import replace
from typing import Any, Callable, Protocol

from sympy.core.function import AppliedUndef, UndefinedFunction

from compiler.errors import DyadError
from compiler.julia.media import Medium, medium_of
from compiler.julia.source import refs
from compiler.syntax import ast


class Evaluator(Protocol):
    """What a handler of object calls may use of the model's evaluator."""
    value: Callable[[ast.Expr, Any], Any]         # a scalar argument's value, in the call's mode
    structural: Callable[[ast.Expr, Any], Any]    # a value known at compile time
    inline: Callable[[Any, list], Any]            # a read Julia function applied to arguments


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


def medium_call(call: ast.Call, scope: Any, evaluator: Evaluator) -> Any:
    """The value of a call with a `path` field (a medium) among its arguments, else None (not
    such a call)."""
    node, lexical = scope.node, scope.lexical
    objects = [path_field_of(arg, node) for arg in call.args]
    if not any(objects):
        return None
    if call.kwargs:
        raise DyadError(f"`{call.function}` with a medium takes no keyword arguments", call.span)
    numeric = [evaluator.value(arg, scope) for arg, obj in zip(call.args, objects) if obj is None]
    position = next(i for i, obj in enumerate(objects) if obj)
    medium = medium_of(node, objects[position], lexical, evaluator.value)
    if medium is None or sum(1 for obj in objects if obj) > 1:
        package = lexical.package
        qualified = call.function if "." in call.function or not package \
            else f"{package}.{call.function}"
        return opaque(qualified, numeric)
    method = medium.method(call.function, position, call.span)
    return evaluator.inline(_specialized(method, position, call.span),
                            [medium.values[field] for field, _ in method.unpacks] + numeric)


def opaque(name: str, arguments: list) -> Any:
    """`name(arguments...)` as a function whose value dyadc cannot compute."""
    return UndefinedFunction(name, bases=(OpaqueJuliaCall,))(*arguments)


def _specialized(method, position: int, span) -> Any:
    """The method with its object parameter replaced by the fields it unpacks, which become its
    first parameters (the caller passes their values)."""
    object_name = method.parameters[position]
    if any(source != object_name for _, source in method.unpacks) or _uses(method, object_name):
        raise DyadError(f"`{method.name}` ({method.file}:{method.line}) uses its medium "
                        f"`{object_name}` other than by `@unpack`, which dyadc cannot follow", span)
    rest = tuple(p for i, p in enumerate(method.parameters) if i != position)
    return replace(method, parameters=tuple(field for field, _ in method.unpacks) + rest,
                   types=(), unpacks=())


def _uses(method, name: str) -> bool:
    shadowed = {field for field, _ in method.unpacks} | {local for local, _ in method.locals}
    if name in shadowed:
        return False
    bodies = [value for _, value in method.locals] + [method.result]
    return any(ref.parts[0].name == name for body in bodies for ref in refs(body))


def opaque_calls(expressions) -> list[str]:
    """Names of the opaque calls in some sympy expressions, sorted, each once."""
    found: set[str] = set()
    for expr in expressions:
        if hasattr(expr, "has") and expr.has(OpaqueJuliaCall):
            found.update(type(call).__name__ for call in expr.atoms(OpaqueJuliaCall))
    return sorted(found)


__all__ = ["Evaluator", "Medium", "OpaqueJuliaCall", "medium_call", "opaque", "opaque_calls",
           "path_field_of"]
