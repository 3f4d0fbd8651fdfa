"""Replaceable components: a typed declaration `sensor::Sensor = Thermometer(k = 2)` in a component
is a subcomponent whose type a user may replace with a modifier `Rig(sensor = Pyrometer())`.

Pure AST helpers (no instantiation here): the constructor call written as the declaration's value
or as a replacing modifier becomes a component type and its modifications, exactly as if the
subcomponent had been declared `sensor = Thermometer(k = 2)`.
"""
from __future__ import annotations

from compiler.errors import DyadError
from compiler.syntax import ast


def constructor(value: ast.Expr | None, name: str, span) -> ast.Call:
    """The component constructor a replaceable is given; anything else is a located error."""
    if isinstance(value, ast.Call):
        return value
    if value is None:
        raise DyadError(f"replaceable component `{name}` has no component", span,
                        hint=f"give one where it is declared (`{name}::Type = Type()`) or where "
                             f"it is used (`Outer({name} = Type())`)")
    raise DyadError(f"`{name}` is a replaceable component; it must be given a component "
                    f"constructor such as `Type()`", getattr(value, "span", None) or span)


def call_modifications(call: ast.Call) -> tuple[ast.Modification, ...]:
    """`T(k = 2, phi(initial = 0))` -> the modifications `k = 2`, `phi(initial = 0)`."""
    mods = [ast.Modification(k.name, k.value, (), False, k.span) for k in call.kwargs]
    for arg in call.args:
        if not isinstance(arg, ast.Call) or "." in arg.function:
            raise DyadError("a component constructor takes named modifiers (`name = value` or "
                            "`name(attribute = value)`)", getattr(arg, "span", None) or call.span)
        mods.append(ast.Modification(arg.function, None, call_modifications(arg), False, arg.span))
    return tuple(mods)


def as_component_decl(decl: ast.TypedDecl, call: ast.Call,
                      with_modifications: bool = True) -> ast.ComponentDecl:
    """The ordinary subcomponent declaration a replaceable stands for."""
    return ast.ComponentDecl(
        name=decl.name, type_name=call.function,
        modifications=call_modifications(call) if with_modifications else (),
        doc=decl.doc, metadata=decl.metadata, condition=None, span=decl.span, link=decl.link)
