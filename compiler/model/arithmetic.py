"""The arithmetic of Dyad operators on evaluated values: scalar and array `+ - * / ^`, their
element-wise forms, comparisons, Julia's integer operators, and building arrays."""
from __future__ import annotations

from typing import Any

import numpy as np
import sympy

from compiler.errors import DyadError, Span
from compiler.model.eval_values import numeric, shape_of
from compiler.model.functions import as_array, is_array
from compiler.model.size_limits import checked_power

COMPARISONS = {"<": sympy.Lt, "<=": sympy.Le, ">": sympy.Gt, ">=": sympy.Ge,
               "==": sympy.Eq, "!=": sympy.Ne}


# Julia's integer operators: `%` and rem() keep the sign of the dividend, mod() that of the
# divisor, `÷` and div() truncate toward zero. Written with floor/sign/abs, which every later pass
# (sympy, CasADi, C code) knows.
INTEGER_OPERATORS = {"%": "rem", "÷": "div"}


def _truncate(x: Any) -> Any:
    return sympy.sign(x) * sympy.floor(sympy.Abs(x))


def integer_operator(name: str, left: Any, right: Any, span: Span | None) -> Any:
    name = INTEGER_OPERATORS.get(name, name)
    a, b = numeric(left, span), numeric(right, span)
    if is_array(a) or is_array(b):
        raise DyadError(f"`{name}` needs scalars", span)
    a, b = sympy.sympify(a), sympy.sympify(b)
    if b.is_zero:
        raise DyadError(f"`{name}` by zero", span)
    if name == "mod":
        return a - b * sympy.floor(a / b)
    if name == "rem":
        return a - b * _truncate(a / b)
    return _truncate(a / b)


def arith(op: str, left: Any, right: Any, span: Span | None) -> Any:
    la, ra = is_array(left), is_array(right)
    if op.startswith(".") and op != ".":
        base = op[1:]
        if la and ra and left.shape != right.shape:
            raise mismatch(op, left, right, span)
        return apply_operator(base, left, right, span)
    if op in ("+", "-"):
        if la != ra:
            raise DyadError(f"cannot `{op}` a scalar and an array of shape "
                            f"{shape_of(left if la else right)}; use `.{op}`", span)
        if la and left.shape != right.shape:
            raise mismatch(op, left, right, span)
        return apply_operator(op, left, right)
    if op == "*":
        if la and ra:
            if left.ndim == 2 and right.ndim in (1, 2) and left.shape[1] == right.shape[0]:
                return left @ right
            if left.ndim == 1 and right.ndim == 2 and right.shape[0] == 1:
                return np.outer(left, right[0])
            raise mismatch(op, left, right, span, hint="use dot(a, b) or `.*` for element-wise")
        return apply_operator(op, left, right)
    if op == "/":
        if ra:
            raise DyadError("cannot divide by an array", span)
        return apply_operator(op, left, right)
    if op == "^":
        if la or ra:
            raise DyadError("`^` needs scalars; use `.^` for element-wise powers", span)
        return checked_power(left, right, span)
    raise DyadError(f"unknown operator `{op}`", span)


def apply_operator(op: str, left: Any, right: Any, span: Span | None = None) -> Any:
    if op == "+":
        return left + right
    if op == "-":
        return left - right
    if op == "*":
        return left * right
    if op == "/":
        return left / right
    if op == "^":
        if is_array(left) or is_array(right):
            return np.vectorize(lambda a, b: checked_power(a, b, span), otypes=[object])(left, right)
        return checked_power(left, right, span)
    raise ValueError(op)


def mismatch(op: str, left: Any, right: Any, span: Span | None, hint: str | None = None
              ) -> DyadError:
    return DyadError(f"array size mismatch in `{op}`: {shape_of(left)} and {shape_of(right)}",
                     span, hint=hint)


def stack(values: list[Any], span: Span | None) -> Any:
    if not values:
        return np.empty(0, dtype=object)
    shapes = {shape_of(v) for v in values}
    if len(shapes) > 1:
        raise DyadError(f"array literal elements have different shapes: "
                        f"{', '.join(str(s) for s in sorted(shapes))}", span)
    shape = shapes.pop()
    if shape == ():
        return as_array(values)
    out = np.empty((len(values),) + shape, dtype=object)
    for i, v in enumerate(values):
        out[i] = v
    return out


def filled(value: Any, shape: tuple[int, ...]) -> np.ndarray:
    out = np.empty(shape, dtype=object)
    for index in np.ndindex(*shape):
        out[index] = value
    return out
