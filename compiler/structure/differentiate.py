"""Partial derivatives of sympy expressions, memoized: the same trees `sympy.diff` builds, faster.

The structure passes differentiate every equation by every unknown it contains, some pairs
several times (time derivatives in index reduction, solvability in tearing, pivoting in dummy
derivative selection). `sympy.diff` pays its generic `Derivative` machinery at every node (for
each symbol even a Piecewise in the order of differentiation) and sympy's bounded cache forgets
the results on large models, which made differentiation most of the compile time of a chain.

`partial(expr, symbol)` applies, for Add, Mul, Pow and ordinary functions, exactly the rule the
node's own class applies inside `sympy.diff` (same products and sums, built in the same order,
so the result is the identical tree); any other node is handed to `sympy.diff` itself. Results
are kept in a bounded memo keyed by (expression, symbol).
"""
from __future__ import annotations

import sympy
from sympy.core.function import ArgumentIndexError, Function
from sympy.ntheory.multinomial import multinomial_coefficients_iterator

from compiler.model.symbols import free_symbols, plain_function

_MEMO_LIMIT = 500_000                        # entries; cleared when full (values are re-derivable)
_memo: dict[tuple[sympy.Basic, sympy.Symbol], sympy.Expr] = {}


def partial(expr: sympy.Expr, symbol: sympy.Symbol) -> sympy.Expr:
    """d expr / d symbol, structurally equal to `sympy.diff(expr, symbol)`."""
    if max(len(_memo), len(_finite_memo)) > _MEMO_LIMIT:
        _memo.clear()
        _finite_memo.clear()
    return _partial(expr, symbol)


def _partial(expr: sympy.Expr, symbol: sympy.Symbol) -> sympy.Expr:
    key = (expr, symbol)
    found = _memo.get(key)
    if found is None:
        found = _derive(expr, symbol)
        _memo[key] = found
    return found


def _derive(expr: sympy.Expr, symbol: sympy.Symbol) -> sympy.Expr:
    if symbol not in free_symbols(expr):
        return sympy.S.Zero                  # Derivative's quick exit
    if expr is symbol or (expr.is_Symbol and expr == symbol):
        return sympy.S.One
    kind = type(expr)
    if kind is sympy.Add:                    # Add._eval_derivative
        return expr.func(*[_partial(a, symbol) for a in expr.args])
    if kind is sympy.Mul:                    # Mul._eval_derivative_n_times with n = 1 (Leibniz)
        args = expr.args
        terms = []
        finite = _finite(expr)
        for orders, coefficient in multinomial_coefficients_iterator(len(args), 1):
            factors = [_partial(a, symbol) if k else a for k, a in zip(orders, args)]
            if finite and any(f is sympy.S.Zero for f in factors):
                continue                     # 1 * Mul(..., 0, ...) is 0, which Add drops
            product = sympy.Mul(*factors)
            terms.append(product if coefficient == 1 else coefficient * product)   # Mul drops a 1
        return sympy.Add(*terms)
    if kind is sympy.Pow:                    # Pow._eval_derivative
        base, exponent = expr.base, expr.exp
        dbase = _partial(base, symbol)
        dexp = _partial(exponent, symbol)
        return expr * (dexp * sympy.log(base) + dbase * exponent / base)
    if plain_function(kind):                # Function._eval_derivative: the chain rule
        terms = []
        for i, a in enumerate(expr.args, start=1):
            da = _partial(a, symbol)
            if da.is_zero:
                continue
            try:
                df = expr.fdiff(i)
            except ArgumentIndexError:
                df = Function.fdiff(expr, i)
            terms.append(df * da)
        result = sympy.Add(*terms)
        if not result.has(sympy.Derivative, sympy.Subs):
            return result
    return sympy.diff(expr, symbol)


_INFINITE = (sympy.S.NaN, sympy.S.ComplexInfinity, sympy.S.Infinity, sympy.S.NegativeInfinity)
_finite_memo: dict[sympy.Basic, bool] = {}


def _finite(expr: sympy.Basic) -> bool:
    """No nan or infinity anywhere in `expr`: then 0 times any factor of it is 0 (0 * oo is nan)."""
    found = _finite_memo.get(expr)
    if found is None:
        if expr.args:
            found = all(_finite(a) for a in expr.args)
        else:
            found = not any(expr is s for s in _INFINITE)
        _finite_memo[expr] = found
    return found
