"""Generic traversal of the syntax tree (compiler/syntax/ast.py) for the metamorphic rewrites.

Nodes are frozen dataclasses; `transform` rebuilds a node bottom-up with a function applied to
every node, `nodes` lists them. Index expressions (`v[1]`), array sizes and iterator ranges are
structure, not arithmetic: `arithmetic_nodes` skips them, so that a rewrite of numbers or
subexpressions never turns an index into `1.0`.
"""
from __future__ import annotations

import dataclasses
from typing import Callable, Iterator

from compiler.syntax import ast

SPANLESS = ("span", "text")


def is_node(value) -> bool:
    return dataclasses.is_dataclass(value) and not isinstance(value, type)


def _children(node):
    for field in dataclasses.fields(node):
        if field.name in SPANLESS:
            continue
        yield field.name, getattr(node, field.name)


def transform(node, function: Callable, enter: Callable = lambda n: True):
    """`node` rebuilt with `function` applied to every node bottom-up (a node for which `enter`
    is false is passed to `function` without its children rebuilt)."""
    if isinstance(node, tuple):
        items = tuple(transform(item, function, enter) for item in node)
        return node if all(a is b for a, b in zip(items, node)) else items
    if not is_node(node):
        return node
    if enter(node):
        changes = {}
        for name, value in _children(node):
            new = transform(value, function, enter)
            if new is not value:
                changes[name] = new
        if changes:
            node = dataclasses.replace(node, **changes)
    return function(node)


def nodes(node, enter: Callable = lambda n: True) -> Iterator:
    """Every node under `node` (itself included), parents before children."""
    if isinstance(node, tuple):
        for item in node:
            yield from nodes(item, enter)
        return
    if not is_node(node):
        return
    yield node
    if enter(node):
        for _, value in _children(node):
            yield from nodes(value, enter)


def arithmetic(node) -> bool:
    """Whether to descend into `node` when looking at arithmetic: not into a reference's indices
    (a Ref's parts), array sizes (TypeSpec), iterators or metadata-bearing modifications' names."""
    return not isinstance(node, (ast.Ref, ast.TypeSpec, ast.Iterator, ast.Range))


def refs_to(node, name: str) -> bool:
    """Whether `node` mentions `name` as the first part of a reference."""
    return any(isinstance(n, ast.Ref) and n.parts[0].name == name for n in nodes(node))


def replace_ref(node, name: str, replacement):
    """`node` with every scalar reference `name` (no indices, no further parts) replaced."""
    def swap(n):
        if isinstance(n, ast.Ref) and len(n.parts) == 1 and n.parts[0].name == name and not n.parts[0].indices:
            return replacement
        return n
    return transform(node, swap)


def rename_ref(node, old: str, new: str):
    """`node` with every reference whose first part is `old` renamed to start with `new`."""
    def swap(n):
        if isinstance(n, ast.Ref) and n.parts[0].name == old:
            return dataclasses.replace(n, parts=(dataclasses.replace(n.parts[0], name=new),) + n.parts[1:])
        return n
    return transform(node, swap)
