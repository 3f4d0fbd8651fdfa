"""Values as the evaluator computes with them: conditions and their 1/0 reading, scalars known at
compile time, shapes, selections, and the time derivative by the chain rule.

A value is a sympy scalar, a numpy object array of sympy scalars (vectors, matrices; 1-based in
the language, 0-based here), or a Python str. Component arrays are numpy object arrays of instance
nodes, so indexing works the same way for both.
"""
from __future__ import annotations

from typing import Any

import numpy as np
import sympy
from sympy.core.relational import Relational
from sympy.logic.boolalg import BooleanAtom, BooleanFunction

from compiler.errors import DyadError, Span
from compiler.model.eval_scope import DerivativeTracker
from compiler.model.flat import TIME, der_name
from compiler.model.functions import is_array

# sympy.Symbol is itself a sympy Boolean, so conditions are recognised by these classes instead.
CONDITION_TYPES = (Relational, BooleanFunction, BooleanAtom)


def is_node_like(value: Any) -> bool:
    return hasattr(value, "member") and hasattr(value, "path")


def is_node_array(value: Any) -> bool:
    return is_array(value) and value.size > 0 and is_node_like(value.flat[0])


def to_bool(value: Any, span: Span | None) -> Any:
    if isinstance(value, CONDITION_TYPES):
        return value
    if is_array(value) or isinstance(value, str):
        raise DyadError("a condition must be a scalar", span)
    if value.is_Number:
        return sympy.true if value != 0 else sympy.false
    # A Boolean variable is 1 or 0 (Booleans are numbers in Dyad); "above one half" says the same
    # for those values and, unlike `!= 0`, crosses zero, so the run can locate where it changes.
    return sympy.Gt(value, sympy.Rational(1, 2))


def numeric(value: Any, span: Span | None) -> Any:
    """Booleans enter arithmetic as 1/0, a symbolic condition as a 1/0 selection."""
    if isinstance(value, BooleanAtom):
        return sympy.Integer(1 if value else 0)
    if isinstance(value, CONDITION_TYPES):
        # A Boolean is a number in Dyad (true = 1, false = 0): `y = u > 1` on a Boolean output.
        return sympy.Piecewise((sympy.Integer(1), value), (sympy.Integer(0), True))
    if isinstance(value, str):
        raise DyadError("a string cannot be used in arithmetic", span)
    if is_node_like(value) or is_node_array(value):
        raise DyadError(f"`{value.path if is_node_like(value) else 'component array'}` is a "
                        f"component, not a value", span)
    if is_array(value):
        return np.vectorize(lambda v: numeric(v, span), otypes=[object])(value) if value.size else value
    return value


def shape_of(value: Any) -> tuple[int, ...]:
    return tuple(value.shape) if is_array(value) else ()


def structural_int(value: Any, span: Span | None, what: str = "an index") -> int:
    if isinstance(value, BooleanAtom):
        return 1 if value else 0
    if is_array(value) or not getattr(value, "is_number", False):
        raise DyadError(f"{what} must be an integer known at compile time", span)
    if value.is_Integer:            # exact, however large (float() of 10^400 overflows)
        return int(value)
    number = float(value)
    if number != int(number):
        raise DyadError(f"{what} must be an integer, got {number:g}", span)
    return int(number)


def structural_bool(value: Any, span: Span | None) -> bool:
    value = to_bool(value, span)
    if value is sympy.true:
        return True
    if value is sympy.false:
        return False
    raise DyadError("this condition must be known at compile time (structural); use "
                    "ifelse(c, a, b) for a continuous selection", span)


def time_invariant(expr: Any, tracker: DerivativeTracker) -> bool:
    values = expr.ravel().tolist() if is_array(expr) else [expr]
    for value in values:
        for sym in getattr(value, "free_symbols", ()):
            if sym == TIME or tracker.is_unknown(sym.name):
                return False
    return True


def time_derivative(expr: Any, tracker: DerivativeTracker) -> Any:
    """d/dt by the chain rule; unknowns x become der(x) symbols, parameters are constant."""
    if is_array(expr):
        return np.vectorize(lambda e: time_derivative(e, tracker), otypes=[object])(expr)
    if isinstance(expr, sympy.Symbol):
        if tracker.is_unknown(expr.name):
            tracker.note_derivative(expr.name)
            return sympy.Symbol(der_name(expr.name))
        return sympy.Integer(1) if expr == TIME else sympy.Integer(0)
    total = sympy.Integer(0)
    for sym in sorted(expr.free_symbols, key=lambda s: s.name):
        if sym == TIME:
            total += sympy.diff(expr, sym)
        elif tracker.is_unknown(sym.name):
            tracker.note_derivative(sym.name)
            total += sympy.diff(expr, sym) * sympy.Symbol(der_name(sym.name))
    return total


def piecewise(cond: Any, then: Any, otherwise: Any, span: Span | None) -> Any:
    if cond is sympy.true:
        return then
    if cond is sympy.false:
        return otherwise
    if is_array(then) or is_array(otherwise):
        if shape_of(then) != shape_of(otherwise):
            raise DyadError(f"the branches have different shapes {shape_of(then)} and "
                            f"{shape_of(otherwise)}", span)
        return np.vectorize(lambda a, b: sympy.Piecewise((a, cond), (b, True)),
                            otypes=[object])(then, otherwise)
    return sympy.Piecewise((then, cond), (otherwise, True))
