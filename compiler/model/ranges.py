"""Ranges with fractional bounds or steps, as Julia builds them: `0:0.1:1` has 11 elements and its
fourth is exactly the double nearest 0.3 (Julia computes `start + i * step` in extended
precision, not by repeated addition). dyadc gets the same numbers by reading each bound as the
shortest decimal that prints it (0.1 as 1/10) and rounding the exact rational `start + i * step`
once. Integer ranges stay in compiler/model/expressions.py."""
from __future__ import annotations

import math
from fractions import Fraction
from typing import Any

import sympy

from compiler.errors import DyadError, Span
from compiler.model.size_limits import check_elements


def is_fractional(value: Any) -> bool:
    """A real number with a fractional part: a range over it is not an integer range (integral
    floats such as 3.0 keep the integer range they always gave)."""
    if not (isinstance(value, (sympy.Float, sympy.Rational)) and value.is_finite):
        return False
    return not value.is_Integer and not float(value).is_integer()


def float_range(start: Any, step: Any, stop: Any, span: Span | None) -> list[sympy.Float]:
    """The elements of `start:step:stop` (`step` None: 1), as Julia gives them."""
    a, s, b = (_exact(v, span) for v in (start, 1 if step is None else step, stop))
    if s == 0:
        raise DyadError("a range step cannot be zero", span)
    count = max(0, math.floor((b - a) / s) + 1)
    check_elements(count, span, "this range")
    return [sympy.Float(float(a + i * s)) for i in range(count)]


def _exact(value: Any, span: Span | None) -> Fraction:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise DyadError(f"a range bound must be a number known at compile time, got {value}",
                        span) from None
    if not math.isfinite(number):
        raise DyadError(f"a range bound must be finite, got {number}", span)
    return Fraction(repr(number))
