"""The free symbols of the flat system's sympy expressions, memoized per node: flattening, alias
elimination and every structure pass ask for them again and again, and sympy recomputes them from
the leaves each time."""
from __future__ import annotations

import sympy
from sympy.core.basic import Basic
from sympy.core.function import Function

_MEMO_LIMIT = 500_000                        # entries; cleared when full (values are re-derivable)
_free_memo: dict[sympy.Basic, frozenset] = {}
_PLAIN: dict[type, bool] = {}


def free_symbols(expr: sympy.Basic) -> frozenset:
    """`expr.free_symbols`, memoized per node."""
    if len(_free_memo) > _MEMO_LIMIT:
        _free_memo.clear()
    return _free(expr)


def _free(expr: sympy.Basic) -> frozenset:
    found = _free_memo.get(expr)
    if found is None:
        if expr.is_Symbol:
            found = frozenset((expr,))
        elif not expr.args:
            found = frozenset(expr.free_symbols)
        elif isinstance(expr, (sympy.Add, sympy.Mul, sympy.Pow)) or plain_function(type(expr)):
            found = frozenset().union(*(_free(a) for a in expr.args))
        else:
            found = frozenset(expr.free_symbols)
        _free_memo[expr] = found
    return found


def plain_function(kind: type) -> bool:
    """A function class that differentiates by the generic chain rule and has its own fdiff (and
    so has the free symbols of its arguments)."""
    plain = _PLAIN.get(kind)
    if plain is None:
        plain = (issubclass(kind, Function)
                 and kind._eval_derivative is Function._eval_derivative
                 and kind._eval_derivative_n_times is Basic._eval_derivative_n_times
                 and kind.fdiff is not Function.fdiff
                 and _class_attribute(kind, "free_symbols") is Basic.__dict__["free_symbols"])
        _PLAIN[kind] = plain
    return plain


def _class_attribute(kind: type, name: str):
    """The attribute `name` as the class defines it for its instances (`kind.free_symbols` would
    be the property of sympy's metaclass FunctionClass, not the one instances use)."""
    return next((c.__dict__[name] for c in kind.__mro__ if name in c.__dict__), None)
