"""A parsed file (compiler.syntax.ast.File) as plain JSON data and back, for the parse cache.

The tree is written in post-order as one flat list, read back by a stack machine, so neither
direction recurses (a 20000-term sum is a 20000-deep chain of BinaryOps). An item of the list is
a constant (None, bool, int, float, str: pushed), or an instruction (a list):

  [k, n]                    pop n items, push them as a tuple (k = TUPLE);
  [k, line, col, eline, ecol]  push the Span of this file at these positions (k = SPAN);
  [k, t]                    pop the fields of node type t (the header's t-th type), push the node;
  [k, i]                    push again the node the i-th node instruction built (k = SHARED: the
                            parser's tree may use one node in two places; it stays one object).

The header lists each node type with its field names; a reader whose classes have other fields
(another version of compiler/syntax/ast.py) gets None, never a tree it misreads. Every field is
kept, those left out of equality (spans, the literal text of numbers) too: a tree read back is
field for field the one written, which is what makes a compile from it bit-identical.

Reading never runs code from the data: it only builds the dataclasses of compiler.syntax.ast.
"""
from __future__ import annotations

import dataclasses
import json

from compiler.errors import Span
from compiler.syntax import ast

CODEC_FORMAT = 1
TUPLE, SPAN, NODE, SHARED = 0, 1, 2, 3
_VISIT, _BUILD, _EMIT = 0, 1, 2
_SCALARS = (str, int, float, bool, type(None))
# The classes a tree may hold: the dataclasses of the AST module (Span is encoded apart).
_NODE_TYPES = {name: cls for name, cls in vars(ast).items()
               if isinstance(cls, type) and dataclasses.is_dataclass(cls) and cls.__module__ == ast.__name__}
_FIELDS = {cls: tuple(f.name for f in dataclasses.fields(cls)) for cls in _NODE_TYPES.values()}


class NotEncodable(ValueError):
    """The tree holds a value the codec does not know (a new kind of field)."""


def encode(tree: ast.File) -> bytes:
    """The JSON bytes of `tree`, or NotEncodable."""
    out: list = []
    type_index: dict[type, int] = {}
    built: dict[int, int] = {}           # id(node) -> its number among node instructions
    keep_alive: list = []                # the ids stay those of live nodes
    # Work in post-order: (_VISIT, value), (_BUILD, node) after its fields, (_EMIT, instruction)
    # after a tuple's items.
    stack: list[tuple[int, object]] = [(_VISIT, tree)]
    while stack:
        step, value = stack.pop()
        if step == _EMIT:
            out.append(value)
        elif step == _BUILD:
            out.append([NODE, type_index.setdefault(type(value), len(type_index))])
            built[id(value)] = len(built)
            keep_alive.append(value)
        elif isinstance(value, _SCALARS):
            out.append(value)
        elif type(value) is tuple:
            stack.append((_EMIT, [TUPLE, len(value)]))
            stack.extend((_VISIT, item) for item in reversed(value))
        elif type(value) is Span:
            if value.file != tree.path:
                raise NotEncodable(f"a span in another file: {value.file}")
            out.append([SPAN, value.line, value.column, value.end_line, value.end_column])
        elif type(value) in _FIELDS:
            number = built.get(id(value))
            if number is not None:
                out.append([SHARED, number])
            else:
                stack.append((_BUILD, value))
                stack.extend((_VISIT, getattr(value, name)) for name in reversed(_FIELDS[type(value)]))
        else:
            raise NotEncodable(f"cannot keep a {type(value).__name__} in the parse cache")
    types = [[cls.__name__, list(_FIELDS[cls])] for cls in sorted(type_index, key=type_index.get)]
    header = {"format": CODEC_FORMAT, "path": tree.path, "types": types}
    try:
        return json.dumps([header, out], separators=(",", ":"), ensure_ascii=False).encode("utf-8")
    except UnicodeEncodeError as err:             # a lone surrogate (only from text in memory)
        raise NotEncodable(str(err)) from None


def decode(data: bytes) -> ast.File | None:
    """The tree `encode` wrote, or None when the data does not fit the current AST classes."""
    try:
        header, items = json.loads(data)
        if header.get("format") != CODEC_FORMAT:
            return None
        path = header["path"]
        classes = []
        for name, fields in header["types"]:
            cls = _NODE_TYPES.get(name)
            if cls is None or list(_FIELDS[cls]) != fields:
                return None
            classes.append((cls, _FIELDS[cls]))
        tree = _run(items, classes, path)
    except (ValueError, TypeError, KeyError, IndexError):
        return None
    return tree if type(tree) is ast.File and tree.path == path else None


def _run(items: list, classes: list, path: str):
    stack: list = []
    push, pop = stack.append, stack.pop
    nodes: list = []
    new = object.__new__
    for item in items:
        if type(item) is not list:
            push(item)
            continue
        kind = item[0]
        if kind == NODE:
            cls, fields = classes[item[1]]
            count = len(fields)
            values = stack[len(stack) - count:] if count else []
            del stack[len(stack) - count:]
            node = new(cls)
            node.__dict__.update(zip(fields, values))     # frozen: fields set as __init__ would
            nodes.append(node)
            push(node)
        elif kind == SPAN:
            span = new(Span)
            span.__dict__.update(file=path, line=item[1], column=item[2], end_line=item[3],
                                 end_column=item[4])
            push(span)
        elif kind == TUPLE:
            count = item[1]
            values = tuple(stack[len(stack) - count:]) if count else ()
            del stack[len(stack) - count:]
            push(values)
        elif kind == SHARED:
            push(nodes[item[1]])
        else:
            raise ValueError(f"unknown instruction {kind}")
    if len(stack) != 1:
        raise ValueError("the data does not hold exactly one tree")
    return stack[0]
