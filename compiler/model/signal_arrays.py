"""Arrays of signal connectors written as a comprehension: `u = [RealInput() for i in 1:n]`.

A signal connector is one variable, so an array of them is one array variable: the comprehension
only says its sizes (one per iterator, in order, before any sizes of the connector's own type),
and `u[i]` is then element i of that variable, in connections and equations alike.
"""
from __future__ import annotations

import dataclasses
from typing import Any

from compiler.errors import DyadError
from compiler.model.expressions import EvalScope, iteration_values
from compiler.model.size_limits import check_shape
from compiler.syntax import ast


def array_type(decl: ast.ComponentDecl, connector: ast.SignalConnectorDef,
               scope: EvalScope) -> ast.TypeSpec:
    """The connector's value type with the comprehension's sizes in front of its own."""
    for modification in decl.modifications:
        used = _iterator_used(modification, {it.variable for it in decl.iterators})
        if used is not None:
            raise DyadError(f"a modifier of the signal connector array `{decl.name}` depends on "
                            f"its iterator `{used}`: every element of such an array shares its "
                            f"modifiers", modification.span,
                            hint=f"give `{decl.name}` modifiers that hold for every element, or "
                                 f"declare the elements one by one")
    sizes = tuple(len(iteration_values(it.iterable, scope)) for it in decl.iterators)
    check_shape(sizes, decl.span, f"the signal connector array `{decl.name}`")
    dims = tuple(ast.Number(size, decl.span) for size in sizes)
    return dataclasses.replace(connector.type, dims=dims + connector.type.dims)


def _iterator_used(node: Any, iterators: set[str]) -> str | None:
    """The first iterator variable `node` (an AST value) refers to, or None."""
    if isinstance(node, ast.Ref):
        if node.parts[0].name in iterators:
            return node.parts[0].name
    if isinstance(node, (tuple, list)):
        return next((found for item in node if (found := _iterator_used(item, iterators))), None)
    if dataclasses.is_dataclass(node) and not isinstance(node, type):
        return _iterator_used([getattr(node, f.name) for f in dataclasses.fields(node)
                               if f.name != "span"], iterators)
    return None
