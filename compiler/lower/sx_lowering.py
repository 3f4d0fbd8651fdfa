"""The memoized walk from sympy to CasADi SX: every sympy node dyadc produces (arithmetic,
elementary functions, relations, Piecewise, interpolated data) becomes an SX node, a shared
subexpression once. Nothing is printed, parsed, expanded or simplified on the way; rational powers
are multiplied out or become square roots where that is exact and cheap."""
from __future__ import annotations

from typing import Callable

import casadi as ca
import sympy

from compiler.errors import DyadError, Span
from compiler.model.interpolation import InterpolatedFunction

# Integer powers up to this are multiplied out (exact, cheap derivatives); larger use constpow.
_MAX_MULTIPLIED_POWER = 16


def _fold(op: Callable) -> Callable:
    def apply(*args):
        result = args[0]
        for a in args[1:]:
            result = op(result, a)
        return result
    return apply


# SX + and * without the Python operator wrappers (which first ask numpy about priority)
_SUM = _fold(ca.plus)
_PRODUCT = _fold(ca.times)

_UNARY = {
    sympy.sin: ca.sin, sympy.cos: ca.cos, sympy.tan: ca.tan,
    sympy.asin: ca.asin, sympy.acos: ca.acos, sympy.atan: ca.atan,
    sympy.sinh: ca.sinh, sympy.cosh: ca.cosh, sympy.tanh: ca.tanh,
    sympy.asinh: ca.asinh, sympy.acosh: ca.acosh, sympy.atanh: ca.atanh,
    sympy.exp: ca.exp, sympy.Abs: ca.fabs, sympy.sign: ca.sign,
    sympy.floor: ca.floor, sympy.ceiling: ca.ceil, sympy.erf: ca.erf,
    sympy.cot: lambda a: 1 / ca.tan(a), sympy.sec: lambda a: 1 / ca.cos(a),
    sympy.csc: lambda a: 1 / ca.sin(a),
}

_RELATIONAL = {
    sympy.StrictLessThan: ca.lt, sympy.LessThan: ca.le,
    sympy.StrictGreaterThan: ca.gt, sympy.GreaterThan: ca.ge,
    sympy.Equality: ca.eq, sympy.Unequality: ca.ne,
}

_VARIADIC = {
    sympy.Min: _fold(ca.fmin), sympy.Max: _fold(ca.fmax),
    sympy.And: _fold(ca.logic_and), sympy.Or: _fold(ca.logic_or),
    sympy.atan2: ca.atan2, sympy.Mod: ca.fmod,
    # sympy writes a condition chosen by a condition as ITE (a locked condition inside a Piecewise)
    sympy.ITE: lambda c, a, b: ca.if_else(c, a, b),
}


class LoweringError(DyadError):
    pass


class SXLowering:
    """Memoized sympy -> SX translation against an environment of named SX values."""

    def __init__(self, env: dict[str, ca.SX], where: str):
        self.env = env
        self.memo: dict[sympy.Basic, ca.SX] = {}
        self.where = where

    def lower(self, expr: sympy.Basic, context: str = "", span: Span | None = None) -> ca.SX:
        expr = sympy.sympify(expr)
        if expr in self.memo:
            return self.memo[expr]
        # Explicit post-order stack: deep expression chains must not hit Python's recursion limit.
        stack: list[tuple[sympy.Basic, bool]] = [(expr, False)]
        while stack:
            node, children_done = stack.pop()
            if node in self.memo:
                continue
            args = self._operands(node)
            if not children_done and any(a not in self.memo for a in args):
                stack.append((node, True))
                stack.extend((a, False) for a in args if a not in self.memo)
                continue
            self.memo[node] = self._convert(node, context, span)
        return self.memo[expr]

    @staticmethod
    def _operands(node: sympy.Basic) -> tuple:
        if node.is_Symbol or node.is_Number or isinstance(node, sympy.NumberSymbol):
            return ()
        if isinstance(node, sympy.Piecewise):
            return tuple(x for pair in node.args for x in pair)
        if isinstance(node, sympy.Pow) and node.exp.is_Rational:
            return (node.base,)
        if isinstance(node, sympy.Mul):
            return tuple(_split_power(f)[0] for f in node.args)
        return node.args

    def _convert(self, node: sympy.Basic, context: str, span: Span | None) -> ca.SX:
        memo = self.memo
        if node.is_Symbol:
            if node.name in self.env:
                return self.env[node.name]
            raise LoweringError(f"unknown symbol '{node}' in {context or self.where}: it is not a "
                                "state, algebraic unknown, parameter, assignment or time", span)
        if node is sympy.true:
            return ca.SX(1.0)
        if node is sympy.false:
            return ca.SX(0.0)
        if node.is_Number or isinstance(node, sympy.NumberSymbol):
            if node is sympy.zoo or node is sympy.nan:
                raise LoweringError(f"undefined value '{node}' (e.g. a division by zero) in "
                                    f"{context or self.where}", span)
            return ca.SX(float(node))
        if isinstance(node, sympy.Add):
            return _SUM(*[memo[a] for a in node.args])
        if isinstance(node, sympy.Mul):
            return self._mul(node)
        if isinstance(node, sympy.Pow):
            if node.exp.is_Rational:
                return _rational_power(memo[node.base], node.exp)
            if node.base is sympy.E:
                return ca.exp(memo[node.exp])
            return ca.power(memo[node.base], memo[node.exp])
        func = node.func
        if func in _UNARY:
            return _UNARY[func](memo[node.args[0]])
        if func is sympy.log:
            value = ca.log(memo[node.args[0]])
            return value / ca.log(memo[node.args[1]]) if len(node.args) == 2 else value
        if func in _VARIADIC:
            return _VARIADIC[func](*[memo[a] for a in node.args])
        if func in _RELATIONAL:
            return _RELATIONAL[func](memo[node.args[0]], memo[node.args[1]])
        if func is sympy.Not:
            return ca.logic_not(memo[node.args[0]])
        if func is sympy.Heaviside:
            a = memo[node.args[0]]
            at_zero = memo[node.args[1]] if len(node.args) > 1 else ca.SX(0.5)
            return ca.if_else(a > 0, 1.0, ca.if_else(a < 0, 0.0, at_zero))
        if isinstance(node, sympy.Piecewise):
            return self._piecewise(node)
        if isinstance(node, InterpolatedFunction):      # tabulated data: compiler/model/interpolation.py
            return ca.SX(node.table.evaluate(memo[node.args[0]], ca.if_else, ca.floor,
                                             memo[node.args[-1]]))
        raise LoweringError(f"cannot lower '{type(node).__name__}' (in `{_short(node)}`) to CasADi "
                            f"in {context or self.where}: unsupported function or construct", span)

    def _mul(self, node: sympy.Mul) -> ca.SX:
        """Factors with negative exponents go to one denominator: a*b/(c*d), not a*b*c^-1*d^-1."""
        numerator: list[ca.SX] = []
        denominator: list[ca.SX] = []
        for factor in node.args:
            base, exponent = _split_power(factor)
            if exponent is None:
                numerator.append(self.memo[factor])
            else:
                target = denominator if exponent < 0 else numerator
                target.append(_rational_power(self.memo[base], abs(exponent)))
        num = _PRODUCT(*numerator) if numerator else ca.SX(1.0)
        if not denominator:
            return num
        return num / _PRODUCT(*denominator)

    def _piecewise(self, node: sympy.Piecewise) -> ca.SX:
        result = ca.SX(float("nan"))                   # no branch applies: undefined
        for value, condition in reversed(node.args):
            if condition is sympy.true:
                result = self.memo[value]
            else:
                result = ca.if_else(self.memo[condition], self.memo[value], result)
        return result


def _split_power(factor: sympy.Basic) -> tuple[sympy.Basic, sympy.Rational | None]:
    """(base, rational exponent) for a power factor with a rational exponent, else (factor, None)."""
    if isinstance(factor, sympy.Pow) and factor.exp.is_Rational:
        return factor.base, factor.exp
    return factor, None


def _rational_power(base: ca.SX, exponent: sympy.Rational) -> ca.SX:
    if exponent.is_Integer:
        n = int(exponent)
        if n == 0:
            return ca.SX(1.0)
        if abs(n) > _MAX_MULTIPLIED_POWER:
            return ca.constpow(base, float(n))
        result = _integer_power(base, abs(n))
        return 1.0 / result if n < 0 else result
    if exponent == sympy.Rational(1, 2):
        return ca.sqrt(base)
    if exponent == sympy.Rational(-1, 2):
        return 1.0 / ca.sqrt(base)
    if exponent.q == 2 and abs(exponent.p) <= _MAX_MULTIPLIED_POWER:
        value = ca.sqrt(base) * _integer_power(base, (abs(exponent.p) - 1) // 2) \
            if abs(exponent.p) > 1 else ca.sqrt(base)
        return 1.0 / value if exponent < 0 else value
    return ca.constpow(base, float(exponent))


def _integer_power(base: ca.SX, n: int) -> ca.SX:
    """base**n by binary exponentiation (n >= 1)."""
    result = None
    square = base
    while n:
        if n & 1:
            result = square if result is None else result * square
        n >>= 1
        if n:
            square = square * square
    return result if result is not None else ca.SX(1.0)


def _short(node: sympy.Basic, limit: int = 80) -> str:
    text = str(node)
    return text if len(text) <= limit else text[:limit - 3] + "..."
