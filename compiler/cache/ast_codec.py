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
_SCALARS = (str, int, float, bool, type(None))
# The classes a tree may hold: the dataclasses of the AST module (Span is encoded apart).
_NODE_TYPES = {name: cls for name, cls in vars(ast).items()
               if isinstance(cls, type) and dataclasses.is_dataclass(cls) and name in ast.__all__}
_FIELDS = {cls: tuple(f.name for f in dataclasses.fields(cls)) for cls in _NODE_TYPES.values()}
_REVERSED_FIELDS = {cls: names[::-1] for cls, names in _FIELDS.items()}
# Built by __init__ (slower) only where __init__ does more than set the fields.
_NEEDS_INIT = frozenset(cls for cls in _NODE_TYPES.values()
                        if hasattr(cls, "__post_init__") or hasattr(cls, "__slots__")
                        or any(not f.init for f in dataclasses.fields(cls)))
_SCALAR_TYPES = frozenset(_SCALARS)


class NotEncodable(ValueError):
    """The tree holds a value the codec does not know (a new kind of field)."""


class _Build:
    """On the encoder's stack: write the node instruction of `node`, whose fields are written."""
    __slots__ = ("node",)

    def __init__(self, node):
        self.node = node


def encode(tree: ast.File) -> bytes:
    """The JSON bytes of `tree`, or NotEncodable."""
    out: list = []
    write = out.append
    type_index: dict[type, int] = {}
    built: dict[int, int] = {}           # id(node) -> its number among node instructions
    keep_alive: list = []                # the ids stay those of live nodes
    # Post-order with one stack of values still to write, a _Build after the fields of its node
    # and a tuple's instruction (a list: the tree holds no lists) after its items.
    stack: list = [tree]
    pop, push, extend = stack.pop, stack.append, stack.extend
    while stack:
        value = pop()
        kind = type(value)
        if kind in _SCALAR_TYPES or kind is list:
            write(value)
        elif kind is _Build:
            node = value.node
            write([NODE, type_index.setdefault(type(node), len(type_index))])
            built[id(node)] = len(built)
            keep_alive.append(node)
        elif kind is tuple:
            push([TUPLE, len(value)])
            extend(reversed(value))
        elif kind is Span:
            if value.file != tree.path:
                raise NotEncodable(f"a span in another file: {value.file}")
            write([SPAN, value.line, value.column, value.end_line, value.end_column])
        elif kind in _REVERSED_FIELDS:
            number = built.get(id(value))
            if number is not None:
                write([SHARED, number])
            else:
                push(_Build(value))
                fields = value.__dict__ if kind not in _NEEDS_INIT else None
                extend([fields[name] if fields is not None else getattr(value, name)
                        for name in _REVERSED_FIELDS[kind]])
        elif isinstance(value, _SCALARS):         # a str subclass (a lark Token) is written as str
            write(value)
        else:
            raise NotEncodable(f"cannot keep a {kind.__name__} in the parse cache")
    types = [[cls.__name__, list(_FIELDS[cls])] for cls in sorted(type_index, key=type_index.get)]
    header = {"format": CODEC_FORMAT, "path": tree.path, "types": types}
    try:
        return json.dumps([header, out], separators=(",", ":"), ensure_ascii=False).encode("utf-8")
    except UnicodeEncodeError as err:             # a lone surrogate (only from text in memory)
        raise NotEncodable(str(err)) from None


def decode(data: bytes, path: str | None = None) -> ast.File | None:
    """The tree `encode` wrote, or None when the data does not fit the current AST classes.
    `path`: the file the tree is read for, in place of the one it was parsed at (the shipped
    library's trees are made where the wheel is built: library_trees.py)."""
    try:
        header, items = json.loads(data)
        if header.get("format") != CODEC_FORMAT:
            return None
        written = header["path"]
        path = written if path is None else path
        classes = []
        for name, fields in header["types"]:
            cls = _NODE_TYPES.get(name)
            if cls is None or list(_FIELDS[cls]) != fields:
                return None
            classes.append((cls, _FIELDS[cls]))
        tree = _run(items, classes, path)
    except (ValueError, TypeError, KeyError, IndexError):
        return None
    if type(tree) is not ast.File or tree.path != written:
        return None
    if path != written:
        tree.__dict__["path"] = path         # still being built: the spans already name `path`
    return tree


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
            if cls in _NEEDS_INIT:
                node = cls(*values)
            else:
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
