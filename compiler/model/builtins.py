"""The one table of Dyad's built-in functions, used for models and analyses alike.

Each entry is either a function of evaluated arguments (compiler/model/functions.py: `sin`,
`max`, `dot`, ...) or a form that needs its call unevaluated: the evaluation mode (`der`), a
condition that selects one branch (`ifelse`), or sizes known at compile time (`zeros`, `size`).
Aliases are other spellings of an entry (`D` for `der`, Julia's `maximum` for `max`). The "did
you mean" hint for an unknown function is drawn from this table and the library's functions, so
the two cannot drift apart.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np
import sympy

from compiler.errors import DyadError, Span, closest
from compiler.model.arithmetic import filled, integer_operator
from compiler.model.eval_scope import EvalScope, Mode
from compiler.model.eval_values import numeric, piecewise, shape_of, structural_int, \
    time_derivative, time_invariant, to_bool
from compiler.model.functions import ELEMENTARY, GLOBAL_REGISTRY, FunctionImpl, \
    FunctionRegistry, as_array
from compiler.model.size_limits import check_shape
from compiler.syntax import ast

Evaluate = Callable[[ast.Expr, EvalScope, Mode], Any]
Form = Callable[[ast.Call, EvalScope, Mode, Evaluate], Any]


@dataclass(frozen=True)
class Builtin:
    """A built-in function: `function` takes evaluated arguments, `form` the call itself."""
    name: str
    function: FunctionImpl | None = None
    form: Form | None = None
    aliases: tuple[str, ...] = ()


def _integer(call: ast.Call, scope: EvalScope, mode: Mode, evaluate: Evaluate) -> Any:
    if call.kwargs:
        raise DyadError(f"`{call.function}` takes no keyword arguments", call.span)
    if len(call.args) != 2:
        raise DyadError(f"`{call.function}` takes two arguments", call.span)
    return integer_operator(call.function, evaluate(call.args[0], scope, mode),
                            evaluate(call.args[1], scope, mode), call.span)


def _not(call: ast.Call, scope: EvalScope, mode: Mode, evaluate: Evaluate) -> Any:
    """`not(c)` is `!c`."""
    if len(call.args) != 1 or call.kwargs:
        raise DyadError("`not` takes one argument", call.span)
    return sympy.Not(to_bool(evaluate(call.args[0], scope, mode), call.span))


def _der(call: ast.Call, scope: EvalScope, mode: Mode, evaluate: Evaluate) -> Any:
    """The time derivative; `D(x)` is Dyad's spelling of der(x)."""
    span = call.span
    if len(call.args) != 1:
        raise DyadError(f"`{call.function}` takes one argument", span)
    if mode is not Mode.SYMBOLIC:
        raise DyadError("`der` cannot be used in a parameter expression", span)
    value = numeric(evaluate(call.args[0], scope, mode), span)
    if time_invariant(value, scope.tracker):
        what = f"`{call.args[0].dotted}`" if isinstance(call.args[0], ast.Ref) else "this"
        raise DyadError(f"der of {what}: it does not depend on time (a parameter or "
                        f"constant has no derivative)", span)
    return time_derivative(value, scope.tracker)


def _ifelse(call: ast.Call, scope: EvalScope, mode: Mode, evaluate: Evaluate) -> Any:
    span = call.span
    if len(call.args) != 3:
        raise DyadError("`ifelse` takes three arguments (condition, then, else)", span)
    cond = to_bool(evaluate(call.args[0], scope, mode), span)
    if cond is sympy.true:
        return evaluate(call.args[1], scope, mode)
    if cond is sympy.false:
        return evaluate(call.args[2], scope, mode)
    return piecewise(cond, numeric(evaluate(call.args[1], scope, mode), span),
                     numeric(evaluate(call.args[2], scope, mode), span), span)


def _shape(args: tuple[ast.Expr, ...], scope: EvalScope, span: Span | None,
           evaluate: Evaluate) -> tuple[int, ...]:
    return check_shape(tuple(structural_int(evaluate(a, scope, Mode.STRUCTURAL), span,
                                            "an array size") for a in args), span, "this array")


def _constant_array(call: ast.Call, scope: EvalScope, mode: Mode, evaluate: Evaluate) -> Any:
    """`zeros(n, ...)`, `ones(n, ...)`."""
    shape = _shape(call.args, scope, call.span, evaluate)
    return filled(sympy.Integer(0 if call.function == "zeros" else 1), shape)


def _fill(call: ast.Call, scope: EvalScope, mode: Mode, evaluate: Evaluate) -> Any:
    if len(call.args) < 2:
        raise DyadError("`fill` takes a value and at least one size", call.span)
    value = numeric(evaluate(call.args[0], scope, mode), call.span)
    return filled(value, _shape(call.args[1:], scope, call.span, evaluate))


def _reshape(call: ast.Call, scope: EvalScope, mode: Mode, evaluate: Evaluate) -> Any:
    """Julia's `reshape(a, m, n, ...)`: the elements of `a` taken in Julia's column-major order
    and laid out in the new sizes (`reshape([1, 2, 3, 4], 2, 2)` is `[1 3; 2 4]`)."""
    if len(call.args) < 2:
        raise DyadError("`reshape` takes an array and at least one size", call.span)
    value = numeric(evaluate(call.args[0], scope, mode), call.span)
    shape = _shape(call.args[1:], scope, call.span, evaluate)
    elements = np.empty(shape_of(value), dtype=object)
    elements[...] = value
    count = int(np.prod(shape, dtype=int))
    if elements.size != count:
        raise DyadError(f"`reshape` cannot lay out {elements.size} element(s) in sizes "
                        f"{', '.join(str(n) for n in shape)} ({count} elements)", call.span)
    return elements.reshape(shape, order="F")


def _size(call: ast.Call, scope: EvalScope, mode: Mode, evaluate: Evaluate) -> Any:
    span = call.span
    if not 1 <= len(call.args) <= 2:
        raise DyadError("`size` takes an array and optionally a dimension", span)
    # A size is known at compile time even when the elements are unknowns: read the array
    # symbolically (in a parameter expression, `size(u, 1)` of a variable `u` is allowed).
    shape = shape_of(numeric(evaluate(call.args[0], scope, Mode.SYMBOLIC), span))
    if len(call.args) == 2:
        dim = structural_int(evaluate(call.args[1], scope, Mode.STRUCTURAL), span)
        if dim < 1:
            raise DyadError(f"`size`: dimension {dim} out of range", span)
        # as in Julia, a scalar (and any array past its last dimension) has size 1
        return sympy.Integer(shape[dim - 1] if dim <= len(shape) else 1)
    return as_array([sympy.Integer(s) for s in shape])


_FORMS = [Builtin("mod", form=_integer), Builtin("rem", form=_integer),
          Builtin("div", form=_integer), Builtin("not", form=_not),
          Builtin("der", form=_der, aliases=("D",)), Builtin("ifelse", form=_ifelse),
          Builtin("zeros", form=_constant_array), Builtin("ones", form=_constant_array),
          Builtin("fill", form=_fill), Builtin("reshape", form=_reshape),
          Builtin("size", form=_size)]
# Julia's reductions over an array: min/max take arrays too
_ALIASES = {"min": ("minimum",), "max": ("maximum",)}

BUILTINS: dict[str, Builtin] = {
    **{b.name: b for b in _FORMS},
    **{name: Builtin(name, function=impl, aliases=_ALIASES.get(name, ()))
       for name, impl in ELEMENTARY.items()},
}
_SPELLINGS = {alias: entry for entry in BUILTINS.values() for alias in (entry.name, *entry.aliases)}


def builtin(name: str) -> Builtin | None:
    """The entry that `name` (a name or an alias) spells, else None."""
    return _SPELLINGS.get(name)


def known_function_names(registry: FunctionRegistry = GLOBAL_REGISTRY) -> list[str]:
    """Every function name a model may call: the built-ins and their aliases, the library's."""
    return sorted(set(_SPELLINGS) | set(registry.names()))


def suggest_function(name: str, registry: FunctionRegistry = GLOBAL_REGISTRY) -> str | None:
    """The known function closest to a misspelt `name`; an alias suggests its entry's name."""
    candidates = known_function_names(registry)
    match = closest(name, candidates)
    if not match:
        short = {c.rsplit(".", 1)[-1]: c for c in candidates}
        found = closest(name.rsplit(".", 1)[-1], short)
        match = [short[found[0]]] if found else []
    if not match:
        return None
    entry = builtin(match[0])
    return entry.name if entry is not None else match[0]
