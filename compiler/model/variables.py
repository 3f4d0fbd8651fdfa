"""Unknowns of an instance: a variable, a connector field or a signal connector, scalar or array,
with its type, flat element names, binding and attributes (`guess`, `units`, ...)."""
from __future__ import annotations

from typing import Any

import numpy as np
import sympy

from compiler.errors import DyadError, Span, suggest_name
from compiler.model.expressions import EvalScope, Lexical, Mode, evaluate, structural_int
from compiler.model.size_limits import check_shape
from compiler.model.library import Resolved
from compiler.model.templates import BoundMod, TypeInfo, resolve_value_type
from compiler.syntax import ast

VARIABLE_ATTRIBUTES = ("initial", "guess", "start", "units", "min", "max", "state_priority",
                       "fixed", "description")


PARAMETER_ATTRIBUTES = ("units", "min", "max", "description")


def join_path(parent: str, name: str) -> str:
    return f"{parent}.{name}" if parent else name


def element_names(base: str, shape: tuple[int, ...]) -> list[str]:
    """Flat scalar names of an array: `A[1,2]` (1-based, row-major)."""
    if not shape:
        return [base]
    return [f"{base}[{','.join(str(i + 1) for i in index)}]" for index in np.ndindex(*shape)]


def symbols_for(base: str, shape: tuple[int, ...]) -> Any:
    if not shape:
        return sympy.Symbol(base)
    out = np.empty(shape, dtype=object)
    for index, name in zip(np.ndindex(*shape), element_names(base, shape)):
        out[index] = sympy.Symbol(name)
    return out


def collect_attributes(type_info: TypeInfo, entries: list[BoundMod], own_scope: EvalScope,
                       allowed: tuple[str, ...], name: str) -> dict[str, tuple[ast.Expr, EvalScope]]:
    """Attribute name -> (expression, scope); later sources override earlier ones."""
    out: dict[str, tuple[ast.Expr, EvalScope]] = {}

    def take(mod: ast.Modification, scope: EvalScope) -> None:
        if mod.name not in allowed:
            raise DyadError(f"unknown attribute `{mod.name}` for `{name}`", mod.span,
                            hint=suggest_name(mod.name, list(allowed)))
        if mod.value is not None:
            out[mod.name] = (mod.value, scope)

    for mod, lexical in type_info.attributes:
        take(mod, own_scope.with_lexical(lexical))
    for entry in reversed(entries):
        for nested in entry.mod.nested:
            take(nested, entry.scope)
    return out


class VariableInstance:
    """An unknown (scalar or array) declared by a variable, a connector field or a signal
    connector; `connector_kind` is 'potential', 'flow', 'signal' or None."""

    def __init__(self, node: Any, name: str, decl: Any, type_spec: ast.TypeSpec,
                 lexical: Lexical, entries: list[BoundMod], *, causality: str | None,
                 connector_kind: str | None, binding: ast.Expr | None = None,
                 initial: ast.Expr | None = None, doc: str | None = None):
        self.node = node
        self.name = name
        self.path = join_path(node.path, name)
        self.decl = decl
        self.causality = causality
        self.connector_kind = connector_kind
        self.doc = doc
        self.type = resolve_value_type(type_spec, lexical)
        own_scope = node.scope(lexical)
        self.shape = check_shape(tuple(structural_int(evaluate(d, node.scope(lex), Mode.STRUCTURAL),
                                                      d.span, "an array size") for d, lex in self.type.dims),
                                 getattr(decl, "span", None), f"the array `{self.path}`")
        self.symbols = symbols_for(self.path, self.shape)
        self.names = element_names(self.path, self.shape)
        valued = [e for e in entries if e.mod.value is not None]
        self.binding: tuple[ast.Expr, EvalScope, Span | None] | None = None
        if valued:
            self.binding = (valued[0].mod.value, valued[0].scope, valued[0].mod.span)
        elif binding is not None:
            self.binding = (binding, own_scope, getattr(decl, "span", None))
        self.attributes = collect_attributes(self.type, entries, own_scope, VARIABLE_ATTRIBUTES,
                                              self.path)
        if initial is not None:
            self.attributes["initial"] = (initial, own_scope)

    @property
    def span(self) -> Span | None:
        return getattr(self.decl, "span", None)

    @property
    def is_signal(self) -> bool:
        return self.causality in ("input", "output")


def fill_connector(node: Any, definition: ast.ConnectorDef, resolved: Resolved,
                   outer: list[BoundMod]) -> None:
    """The fields of a connector instance `node`: unknowns, or recorded `path` fields."""
    lexical = Lexical(node.model.library, resolved.package, resolved.file)
    by_name: dict[str, list[BoundMod]] = {}
    for entry in outer:
        by_name.setdefault(entry.mod.name, []).append(entry)
    names = [f.name for f in definition.fields]
    for name, entries in by_name.items():
        if name not in names:
            raise DyadError(f"connector `{definition.name}` has no field `{name}`",
                            entries[0].mod.span, hint=suggest_name(name, names))
    for fld in definition.fields:
        if fld.kind == "path":
            # A path field carries a value of the whole connected path (a fluid medium, a Julia
            # `Native` object) that is neither an unknown nor an equation: it is recorded, and
            # reading it in an expression is an error (see Instance.member).
            node.path_fields[fld.name] = fld.span
            continue
        if fld.kind == "stream":
            raise DyadError("`stream` connector fields are not supported yet", fld.span)
        signal = fld.kind in ("input", "output")
        variable = VariableInstance(
            node, fld.name, fld, fld.type, lexical, by_name.get(fld.name, []),
            causality=fld.kind if signal else None,
            connector_kind="signal" if signal else fld.kind, doc=fld.doc)
        node.variables[fld.name] = variable
        node.model.unknown_names.update(variable.names)
