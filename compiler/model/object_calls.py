"""The registry of calls the evaluator does not compute itself: calls with a Julia object among
their arguments, and functions read from a package's Julia source.

compiler/model/expressions.py asks `object_call` for every call of an equation and `inline` for a
resolved Julia function; it imports neither compiler.julia nor object_values.py. Each handler of
`OBJECT_CALLS` returns the call's value, or None when the call is not its kind:

- `interpolator(u)` through a parameter holding an interpolator (compiler/model/object_values.py);
- `density(port.medium, p)`: the Julia method the medium's struct picks (compiler/julia/objects.py).

`object_part_value` gives `dataset["name"]`, a part of a dataset read as an array (a 2-D table's
axis or data, a dataset's column), for the evaluator's references.

Handlers evaluate Dyad expressions only through the `Evaluator` they are handed, so neither
imports the evaluator and no import cycle passes through them.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Callable

from compiler.errors import DyadError
from compiler.julia import inline as julia_inline
from compiler.julia.objects import medium_call
from compiler.model.object_values import interpolator_call, object_part
from compiler.syntax import ast

OBJECT_CALLS = (interpolator_call, medium_call)


@dataclass(frozen=True)
class Evaluator:
    """The evaluator, as a handler sees it (compiler.julia.objects.Evaluator)."""
    value: Callable[[ast.Expr, Any], Any]         # a numeric argument's value, in the call's mode
    structural: Callable[[ast.Expr, Any], Any]    # a value known at compile time
    inline: Callable[[Any, list], Any]            # a read Julia function applied to arguments


def object_call(call: ast.Call, scope: Any, evaluator: Evaluator) -> Any:
    """The value of `call` by the first handler that takes it, else None (an ordinary call)."""
    scalars = replace(evaluator, value=_scalars_only(evaluator.value, call))
    for handler in OBJECT_CALLS:
        value = handler(call, scope, scalars)
        if value is not None:
            return value
    return None


def inline(function: Any, arguments: list, call: ast.Call, scope: Any,
           evaluate: Callable[[ast.Expr, Any], Any]) -> Any:
    """A function read from Julia source (compiler/julia/inline.py) applied to `arguments`."""
    return julia_inline.inline(function, arguments, call, scope, evaluate)


def _scalars_only(evaluate: Callable[[ast.Expr, Any], Any], call: ast.Call):
    """`evaluate`, refusing array values: an opaque call or a medium's field is a scalar."""
    def scalar(arg: ast.Expr, at: Any) -> Any:
        value = evaluate(arg, at)
        if getattr(value, "shape", ()) != ():
            raise DyadError(f"`{call.function}` with a Julia object takes scalar arguments",
                            getattr(arg, "span", None) or call.span)
        return value
    return scalar


def is_object_part(ref: ast.Ref, scope: Any) -> bool:
    """Is `ref` written `dataset["name"]`, `dataset` a Julia-object parameter of the scope?"""
    first = ref.parts[0]
    return len(ref.parts) == 1 and len(first.indices) == 1 and first.name not in scope.bindings \
        and first.name in getattr(scope.node, "path_fields", {})


def object_part_value(ref: ast.Ref, scope: Any, structural: Callable[[Any, Any], Any]) -> Any:
    """The value of `dataset["name"]` (compiler/model/object_values.py)."""
    return object_part(ref, scope, structural)
