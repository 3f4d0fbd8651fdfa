"""A function read from a package's Julia source, applied by inlining its body.

The body sees only its parameters and its own earlier locals (checked when it was read,
compiler/julia/bodies.py), and its calls resolve in its package. The model's evaluator hands over
the scope of the call (which must offer `bind` and `function_body`) and a way to evaluate an
expression in a scope; nothing here imports compiler.model.
"""
from __future__ import annotations

from typing import Any, Callable

from compiler.errors import DyadError
from compiler.julia.bodies import JuliaFunction
from compiler.syntax import ast

MAX_CALL_DEPTH = 32                   # a function calling itself would never stop being inlined
_DEPTH = " julia call depth"          # a binding key no Dyad name can spell


def inline(function: JuliaFunction, arguments: list, call: ast.Call, scope: Any,
           evaluate: Callable[[ast.Expr, Any], Any]) -> Any:
    """The value of `call` (resolved to `function`) with these evaluated arguments."""
    span = call.span
    if call.kwargs:
        raise DyadError(f"`{call.function}` takes no keyword arguments", span)
    if not function.accepts(len(arguments)):
        raise DyadError(f"`{call.function}` takes {function.arity()} argument(s), got "
                        f"{len(arguments)}", span)
    depth = scope.bindings.get(_DEPTH, 0) + 1
    if depth > MAX_CALL_DEPTH:
        raise DyadError(f"`{call.function}` calls itself more than {MAX_CALL_DEPTH} levels deep",
                        span, hint="dyadc inlines Julia functions; recursion cannot be inlined")
    package = function.name.rpartition(".")[0]
    inner = scope.function_body(package, {**dict(zip(function.parameters, arguments)),
                                          _DEPTH: depth})
    for local, value in function.defaults_after(len(arguments)) + function.locals:
        inner = inner.bind(**{local: evaluate(value, inner)})
    return evaluate(function.result, inner)
