"""Arrays the evaluator builds from expressions: ranges (`1:n`, Julia's float ranges), array
and matrix literals, comprehensions, the values a `for` loop runs through, and indexing.

Each function takes the evaluator as its last argument (as the forms of builtins.py do), so this
module does not import compiler/model/expressions.py, which dispatches to it.
"""
from __future__ import annotations

from typing import Any, Callable

import numpy as np
import sympy

from compiler.errors import DyadError, Note, Span
from compiler.model.arithmetic import stack
from compiler.model.eval_scope import END_BINDING, EvalScope, Mode
from compiler.model.eval_values import numeric, structural_bool, structural_int
from compiler.model.functions import as_array, is_array
from compiler.model.ranges import float_range, is_fractional
from compiler.model.size_limits import check_elements, range_length
from compiler.syntax import ast

Evaluate = Callable[[ast.Expr, EvalScope, Mode], Any]


def iteration_values(expr: ast.Expr, scope: EvalScope, evaluate: Evaluate) -> list[Any]:
    """The values a `for` iterator runs through (structural)."""
    value = evaluate(expr, scope, Mode.STRUCTURAL)
    if is_array(value):
        return list(value.ravel())
    raise DyadError("a `for` loop needs a range or an array to iterate over",
                    getattr(expr, "span", None))


def range_value(expr: ast.Range, scope: EvalScope, mode: Mode,
                evaluate: Evaluate) -> Any:
    """`start:stop` or `start:step:stop`: integers, or Julia's floats when a bound is fractional."""
    bounds = [None if part is None else evaluate(part, scope, Mode.STRUCTURAL)
              for part in (expr.start, expr.step, expr.stop)]
    if any(is_fractional(bound) for bound in bounds):      # `0:0.1:1`: Julia's float range
        return as_array(float_range(*bounds, expr.span))
    start = structural_int(bounds[0], expr.span, "a range bound")
    stop = structural_int(bounds[2], expr.span, "a range bound")
    step = 1
    if expr.step is not None:
        step = structural_int(bounds[1], expr.span, "a range step")
        if step == 0:
            raise DyadError("a range step cannot be zero", expr.span)
    check_elements(range_length(start, stop, step), expr.span, "this range")
    return as_array([sympy.Integer(i) for i in range(start, stop + (1 if step > 0 else -1), step)])


def array_literal(expr: ast.ArrayLit, scope: EvalScope, mode: Mode,
                  evaluate: Evaluate) -> Any:
    """`[a, b]` (elements stacked) or `[a b; c d]` (a matrix, rows of equal length)."""
    if expr.is_matrix:
        rows = []
        for row in expr.elements:
            items = row.elements if isinstance(row, ast.ArrayLit) else (row,)
            values = []
            for item in items:
                v = numeric(evaluate(item, scope, mode), expr.span)
                values.extend(v.ravel().tolist() if is_array(v) else [v])
            rows.append(values)
        if len({len(r) for r in rows}) > 1:
            raise DyadError("the rows of a matrix literal have different lengths", expr.span)
        out = np.empty((len(rows), len(rows[0]) if rows else 0), dtype=object)
        for i, r in enumerate(rows):
            for j, v in enumerate(r):
                out[i, j] = v
        return out
    values = [numeric(evaluate(e, scope, mode), expr.span) for e in expr.elements]
    return stack(values, expr.span)


def comprehension(expr: ast.Comprehension, scope: EvalScope, mode: Mode,
                  evaluate: Evaluate) -> Any:
    """`[f(i, j) for i in r, j in s]`, bounded by the element limit."""
    if expr.is_vector:
        return _vector_comprehension(expr, scope, mode, evaluate)

    def expand(level: int, inner: EvalScope, outer: int) -> Any:
        if level == len(expr.iterators):
            return numeric(evaluate(expr.expr, inner, mode), expr.span)
        it = expr.iterators[level]
        values = iteration_values(it.iterable, inner, evaluate)
        # nested iterators multiply: each level's range may be small, their product not
        check_elements(outer * len(values), expr.span, "this comprehension")
        items = [expand(level + 1, inner.bind(**{it.variable: v}), outer * len(values))
                 for v in values]
        return stack(items, expr.span)
    return expand(0, scope, 1)


def _vector_comprehension(expr: ast.Comprehension, scope: EvalScope, mode: Mode,
                          evaluate: Evaluate) -> Any:
    """`[f(i, j) for i in r if c for j in s(i) if d]`: the elements whose clauses' conditions
    hold, in one vector, the last iterator varying fastest (Julia's order). A condition must be
    known at compile time: it decides how many elements there are."""
    iterators = [(it, clause) for clause in expr.clauses for it in clause.iterators]
    elements: list[Any] = []

    def walk(level: int, inner: EvalScope) -> None:
        if level == len(iterators):
            elements.append(numeric(evaluate(expr.expr, inner, mode), expr.span))
            check_elements(len(elements), expr.span, "this comprehension")
            return
        it, clause = iterators[level]
        last_of_clause = it is clause.iterators[-1]
        for value in iteration_values(it.iterable, inner, evaluate):
            bound = inner.bind(**{it.variable: value})
            if last_of_clause and clause.condition is not None and not _passes(clause.condition, bound):
                continue
            walk(level + 1, bound)
    def _passes(condition: ast.Expr, inner: EvalScope) -> bool:
        try:
            value = evaluate(condition, inner, Mode.STRUCTURAL)
        except DyadError as err:
            if "cannot depend on" not in err.message:     # not a run-time value: another error
                raise
            raise DyadError("the `if` filter of a comprehension must be known when the model is "
                            "compiled: it decides how many elements there are", condition.span,
                            notes=[Note(err.message, err.span)],
                            hint="filter on parameters and iterators, or keep every element and "
                                 "select its value with `ifelse(c, a, 0)`") from None
        return structural_bool(value, condition.span)

    walk(0, scope)
    return stack(elements, expr.span)


def indexed(value: Any, indices: tuple[ast.Expr, ...], name: str, scope: EvalScope,
            span: Span | None, evaluate: Evaluate) -> Any:
    """`value` indexed by `indices`: 1-based positions, `end` bound to each dimension's size, `:`
    keeping a dimension; a position out of bounds is a located error."""
    if not indices:
        return value
    if not is_array(value):
        raise DyadError(f"`{name}` is not an array and cannot be indexed", span)
    if len(indices) > value.ndim:
        raise DyadError(f"`{name}` has {value.ndim} dimension(s) but {len(indices)} indices were "
                        f"given", span)
    result = value
    axis = 0
    for dim, index in enumerate(indices):
        size = value.shape[dim]
        if isinstance(index, ast.Colon):
            axis += 1
            continue
        inner = scope.bind(**{END_BINDING: sympy.Integer(size)})
        picked = evaluate(index, inner, Mode.STRUCTURAL)
        if is_array(picked):
            positions = [structural_int(p, span) for p in picked.ravel()]
            for p in positions:
                _check_bounds(p, size, name, span)
            result = np.take(result, [p - 1 for p in positions], axis=axis)
            axis += 1
        else:
            position = structural_int(picked, span)
            _check_bounds(position, size, name, span)
            result = np.take(result, position - 1, axis=axis)
    if is_array(result) and result.ndim == 0:
        return result.item()
    return result


def _check_bounds(position: int, size: int, name: str, span: Span | None) -> None:
    if not 1 <= position <= size:
        raise DyadError(f"index {position} is out of bounds for `{name}` of size {size}", span)
