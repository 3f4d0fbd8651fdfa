"""Expressions of an analysis block: its parameters substituted into the model's modifiers, and
the numeric value of a field (`stop = 10`, `reltol = 1m`, `stop = 2 * T`).

A field is evaluated by the model's evaluator (compiler/model/expressions.py) with its built-ins,
constants and guards (a power too large to fold, an array too large to build): the analysis is
the scope's node, whose members are its fields and parameters, each evaluated on first use."""
from __future__ import annotations

import dataclasses
from typing import Any, Mapping

import sympy

from compiler.errors import DyadError, Span
from compiler.model.expressions import NOT_FOUND, EvalScope, Lexical, Mode, evaluate, is_array
from compiler.syntax import ast


def substitute(expr: Any, names: Mapping[str, Any], depth: int = 0) -> Any:
    """`expr` with every plain reference to a name of `names` replaced by that name's
    expression (itself substituted). A new tree; `expr` is not changed."""
    if depth > 100:
        raise DyadError("analysis parameters refer to each other in a cycle",
                        getattr(expr, "span", None))
    if isinstance(expr, ast.Ref) and len(expr.parts) == 1 and not expr.parts[0].indices \
            and expr.parts[0].name in names:
        return substitute(names[expr.parts[0].name], names, depth + 1)
    if isinstance(expr, tuple):
        return tuple(substitute(item, names, depth) for item in expr)
    if dataclasses.is_dataclass(expr) and not isinstance(expr, type):
        changes = {f.name: substitute(getattr(expr, f.name), names, depth)
                   for f in dataclasses.fields(expr) if f.name != "span"}
        if all(changes[k] is getattr(expr, k) for k in changes):
            return expr
        return dataclasses.replace(expr, **changes)
    return expr


class AnalysisValues:
    """The fields and parameters of one analysis (expressions by name), evaluated on demand."""

    def __init__(self, name: str, expressions: Mapping[str, Any], lexical: Lexical):
        self.path = f"analysis `{name}`"
        self._expressions = dict(expressions)
        self._values: dict[str, Any] = {}
        self._evaluating: set[str] = set()
        self._scope = EvalScope(self, lexical, _NoUnknowns())

    def member(self, name: str, mode: Mode, span: Span | None) -> Any:
        """The value of field or parameter `name` (the evaluator's node protocol)."""
        if name not in self._expressions:
            return NOT_FOUND
        if name not in self._values:
            if name in self._evaluating:
                raise DyadError("analysis parameters refer to each other in a cycle", span)
            self._evaluating.add(name)
            try:
                self._values[name] = evaluate(self._expressions[name], self._scope, Mode.NUMERIC)
            finally:
                self._evaluating.discard(name)
        return self._values[name]

    def member_names(self) -> list[str]:
        return sorted(self._expressions)

    def number(self, name: str, what: str, span: Span | None) -> float:
        """The value of numeric field `name`, or a located error."""
        expr = self._expressions[name]
        value = self.member(name, Mode.NUMERIC, getattr(expr, "span", None) or span)
        where = getattr(expr, "span", None) or span
        if isinstance(value, str) or is_array(value) or not isinstance(value, sympy.Expr) \
                or not value.is_number:
            raise DyadError(f"{what} must be a number", where)
        if not value.is_extended_real:
            raise DyadError(f"{what} must be a real number, got {value}", where)
        return float(value)


class _NoUnknowns:
    """An analysis has no unknowns: nothing in it has a time derivative."""

    def is_unknown(self, name: str) -> bool:
        return False

    def note_derivative(self, name: str) -> None:
        raise AssertionError("an analysis field has no derivative")


def text(expr: Any) -> str:
    """A field such as `alg = "auto"` or `alg = ODEAlg.Rodas5P()` as written, for notes."""
    if isinstance(expr, ast.String):
        return expr.value
    if isinstance(expr, ast.Call):
        return f"{expr.function}()"
    if isinstance(expr, ast.Ref):
        return expr.dotted
    return type(expr).__name__
