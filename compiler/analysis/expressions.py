"""Expressions of an analysis block: its parameters substituted into the model's modifiers, and
the numeric value of a field (`stop = 10`, `reltol = 1m`, `stop = 2 * T`)."""
from __future__ import annotations

import dataclasses
import math
from typing import Any, Mapping

from compiler.errors import DyadError, Span
from compiler.syntax import ast

_CONSTANTS = {"pi": math.pi, "π": math.pi, "e": math.e, "Inf": math.inf, "inf": math.inf}
_FUNCTIONS = {"sqrt": math.sqrt, "exp": math.exp, "log": math.log, "log10": math.log10,
              "sin": math.sin, "cos": math.cos, "tan": math.tan, "abs": abs,
              "min": min, "max": max}
_BINARY = {"+": lambda a, b: a + b, "-": lambda a, b: a - b, "*": lambda a, b: a * b,
           "/": lambda a, b: a / b, "^": lambda a, b: a ** b, ".+": lambda a, b: a + b,
           ".-": lambda a, b: a - b, ".*": lambda a, b: a * b, "./": lambda a, b: a / b,
           ".^": lambda a, b: a ** b}


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


def number(expr: Any, what: str, span: Span | None) -> float:
    """The value of a numeric field of an analysis, or a located error."""
    value = _evaluate(expr, what, span)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise DyadError(f"{what} must be a number", getattr(expr, "span", None) or span)
    return float(value)


def text(expr: Any) -> str:
    """A field such as `alg = "auto"` or `alg = ODEAlg.Rodas5P()` as written, for notes."""
    if isinstance(expr, ast.String):
        return expr.value
    if isinstance(expr, ast.Call):
        return f"{expr.function}()"
    if isinstance(expr, ast.Ref):
        return expr.dotted
    return type(expr).__name__


def _evaluate(expr: Any, what: str, span: Span | None) -> Any:
    where = getattr(expr, "span", None) or span
    if isinstance(expr, ast.Number):
        return expr.value
    if isinstance(expr, ast.Boolean):
        return expr.value
    if isinstance(expr, ast.String):
        return expr.value
    if isinstance(expr, ast.Ref) and len(expr.parts) == 1 and expr.parts[0].name in _CONSTANTS:
        return _CONSTANTS[expr.parts[0].name]
    if isinstance(expr, ast.UnaryOp) and expr.op in ("-", "+"):
        value = _evaluate(expr.operand, what, span)
        return -value if expr.op == "-" else value
    if isinstance(expr, ast.BinaryOp) and expr.op in _BINARY:
        left, right = _evaluate(expr.left, what, span), _evaluate(expr.right, what, span)
        try:
            return _BINARY[expr.op](left, right)
        except (ArithmeticError, TypeError) as err:
            raise DyadError(f"{what}: cannot evaluate ({err})", where) from None
    if isinstance(expr, ast.Call) and expr.function in _FUNCTIONS and not expr.kwargs:
        args = [_evaluate(a, what, span) for a in expr.args]
        try:
            return _FUNCTIONS[expr.function](*args)
        except (ArithmeticError, TypeError, ValueError) as err:
            raise DyadError(f"{what}: cannot evaluate ({err})", where) from None
    if isinstance(expr, ast.Ref):
        raise DyadError(f"{what}: unknown name `{expr.dotted}`", where,
                        hint="an analysis field may use numbers and the analysis's parameters")
    raise DyadError(f"{what}: dyadc cannot evaluate this expression here", where,
                    hint="write a number, or an arithmetic expression of the analysis's parameters")
