"""The scope an expression is evaluated in: the instance node whose members it names, where it
was written (for function and type names), the unknowns it may differentiate, and local bindings
(loop variables, function parameters). Also the three evaluation modes:

- SYMBOLIC: equations. Variables and ordinary parameters stay symbols; structural parameters and
  constants are replaced by their values.
- NUMERIC: parameter values. Every parameter is replaced by its numeric value; variables and `time`
  are errors. A parameter without a value raises MissingValue.
- STRUCTURAL: like NUMERIC, for array sizes, indices, ranges and `if` conditions; the parameters
  read are recorded as structural (no longer tunable) and a missing value is a located error.
"""
from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import Any, Protocol

from compiler.errors import DyadError, Span, suggest_name
from compiler.model.flat import TIME
from compiler.model.functions import CONSTANTS
from compiler.syntax import ast

class Mode(enum.Enum):
    SYMBOLIC = "symbolic"
    NUMERIC = "numeric"
    STRUCTURAL = "structural"


class MissingValue(Exception):
    """A parameter without a value was needed for a numeric evaluation."""

    def __init__(self, name: str):
        super().__init__(name)
        self.name = name


END_BINDING = "\0end"     # the size of the dimension being indexed, for `end`
NOT_FOUND = object()


class Node(Protocol):
    """An instance in the tree (component or connector), as seen by the evaluator."""
    path: str

    def member(self, name: str, mode: Mode, span: Span | None) -> Any: ...
    def member_names(self) -> list[str]: ...


class DerivativeTracker(Protocol):
    def is_unknown(self, name: str) -> bool: ...
    def note_derivative(self, name: str) -> None: ...


@dataclass(frozen=True)


class Lexical:
    """Where a piece of source was written: resolves function (and type) names."""
    library: Any                    # compiler.model.library.Library (which imports this module)
    package: str
    file: ast.File | None


class EvalScope:
    """Where an expression is evaluated; `bind` and the other methods return new scopes."""
    __slots__ = ("node", "lexical", "bindings", "tracker")

    def __init__(self, node: Node, lexical: Lexical, tracker: DerivativeTracker,
                 bindings: dict[str, Any] | None = None):
        self.node = node
        self.lexical = lexical
        self.tracker = tracker
        self.bindings = bindings or {}

    def bind(self, **values: Any) -> "EvalScope":
        return EvalScope(self.node, self.lexical, self.tracker, {**self.bindings, **values})

    def with_lexical(self, lexical: Lexical) -> "EvalScope":
        return EvalScope(self.node, lexical, self.tracker, self.bindings)

    def function_body(self, package: str, bindings: dict[str, Any]) -> "EvalScope":
        """The scope of an inlined function's body: no component members, only `bindings`, its
        calls resolved in `package`."""
        return EvalScope(FunctionBodyNode(self.node), Lexical(self.lexical.library, package, None),
                         self.tracker, bindings)

    def lookup(self, name: str, mode: Mode, span: Span | None) -> Any:
        if name in self.bindings:
            return self.bindings[name]
        found = self.node.member(name, mode, span)
        if found is not NOT_FOUND and found is not None:
            return found
        if name == "time":
            if mode is not Mode.SYMBOLIC:
                raise DyadError("a parameter expression cannot depend on `time`", span)
            return TIME
        if name in CONSTANTS:
            return CONSTANTS[name]
        hint = suggest_name(name, list(self.bindings) + self.node.member_names())
        where = self.node.path or "the model"
        raise DyadError(f"unknown name `{name}` in {where}", span, hint=hint)


class FunctionBodyNode:
    """The scope node of a Julia function body: it sees no component members."""

    def __init__(self, node: Node):
        self.path = node.path

    def member(self, name: str, mode: Mode, span: Span | None) -> Any:
        return NOT_FOUND

    def member_names(self) -> list[str]:
        return []
