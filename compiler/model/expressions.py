"""AST expressions -> sympy values, inside an instance scope (compiler/model/eval_scope.py: the
scope and the three evaluation modes; eval_values.py: what a value is).

`evaluate` dispatches on the node type: references and indices are resolved here; operators
compute with arithmetic.py; arrays are built by eval_arrays.py; calls go to the one table of
built-ins (builtins.py), then to the registry of object calls (object_calls.py), then to the
library's functions; enum members and `switch` cases come from enums.py. The modules it
dispatches to receive `evaluate` as an argument and never import this one.
"""
from __future__ import annotations

from typing import Any

import sympy

from compiler.errors import DyadError, Span, suggest_name
from compiler.model import eval_arrays, object_calls
from compiler.model.arithmetic import COMPARISONS, INTEGER_OPERATORS, arith, integer_operator
from compiler.model.builtins import builtin
from compiler.model.enums import case_bindings, check_member_call, enum_member_value, \
    selected_case
from compiler.model.eval_scope import END_BINDING, NOT_FOUND, DerivativeTracker, EvalScope, \
    FunctionBodyNode, Lexical, MissingValue, Mode, Node
from compiler.model.eval_values import CONDITION_TYPES, is_node_array, is_node_like, numeric, \
    piecewise, shape_of, structural_bool, structural_int, time_derivative, time_invariant, to_bool
from compiler.model.functions import FunctionCallError, FunctionImpl, is_array
from compiler.syntax import ast

__all__ = ["CONDITION_TYPES", "END_BINDING", "NOT_FOUND", "DerivativeTracker", "EvalScope",
           "FunctionBodyNode", "Lexical", "MissingValue", "Mode", "Node", "apply_indices",
           "enum_member_value", "evaluate", "is_array", "is_node_array", "is_node_like",
           "iteration_values", "numeric", "resolve_ref", "shape_of", "structural_bool",
           "structural_int", "switch_branch", "time_derivative", "time_invariant", "to_bool"]


def evaluate(expr: ast.Expr, scope: EvalScope, mode: Mode) -> Any:
    handler = _HANDLERS.get(type(expr))
    if handler is None:
        raise DyadError(f"unsupported expression {type(expr).__name__}", getattr(expr, "span", None))
    return handler(expr, scope, mode)


def _number(expr: ast.Number, scope: EvalScope, mode: Mode) -> Any:
    if isinstance(expr.value, bool):
        return sympy.Integer(int(expr.value))
    if isinstance(expr.value, int):
        return sympy.Integer(expr.value)
    return sympy.Float(expr.value)


def _string(expr: ast.String, scope: EvalScope, mode: Mode) -> Any:
    return expr.value


def _boolean(expr: ast.Boolean, scope: EvalScope, mode: Mode) -> Any:
    return sympy.true if expr.value else sympy.false


def _end(expr: ast.End, scope: EvalScope, mode: Mode) -> Any:
    if END_BINDING not in scope.bindings:
        raise DyadError("`end` can only be used inside an index", expr.span)
    return scope.bindings[END_BINDING]


def _colon(expr: ast.Colon, scope: EvalScope, mode: Mode) -> Any:
    raise DyadError("`:` can only be used as an index", expr.span)


def resolve_ref(ref: ast.Ref, scope: EvalScope, mode: Mode) -> Any:
    """The value or node a reference names (components and connectors are returned as nodes)."""
    first = ref.parts[0]
    if len(ref.parts) > 1 and not any(p.indices for p in ref.parts) \
            and first.name not in scope.bindings and first.name not in scope.node.member_names():
        member = enum_member_value(ref.dotted, scope.lexical, ref.span)
        if member is not None:
            return member
    if object_calls.is_object_part(ref, scope):      # `table["velocity"]`: data of a dataset
        return object_calls.object_part_value(ref, scope,
                                              lambda arg, at: evaluate(arg, at, Mode.STRUCTURAL))
    current = scope.lookup(first.name, mode, ref.span)
    current = apply_indices(current, first.indices, first.name, scope, ref.span)
    walked = first.name
    for part in ref.parts[1:]:
        if not is_node_like(current):
            kind = "an array of components" if is_node_array(current) else "not a component"
            raise DyadError(f"`{walked}` is {kind}; cannot access `.{part.name}`", ref.span)
        found = current.member(part.name, mode, ref.span)
        if found is NOT_FOUND or found is None:
            raise DyadError(f"`{walked}` has no member `{part.name}`", ref.span,
                            hint=suggest_name(part.name, current.member_names()))
        current = apply_indices(found, part.indices, f"{walked}.{part.name}", scope, ref.span)
        walked = f"{walked}.{part.name}"
    return current


def _ref(expr: ast.Ref, scope: EvalScope, mode: Mode) -> Any:
    value = resolve_ref(expr, scope, mode)
    if is_node_like(value) or is_node_array(value):
        raise DyadError(f"`{expr.dotted}` is a component or connector, not a value", expr.span)
    return value


def apply_indices(value: Any, indices: tuple[ast.Expr, ...], name: str, scope: EvalScope,
                  span: Span | None) -> Any:
    """`value` indexed by `indices` (1-based, `end` and `:` as Dyad reads them)."""
    return eval_arrays.indexed(value, indices, name, scope, span, evaluate)


def iteration_values(expr: ast.Expr, scope: EvalScope) -> list[Any]:
    """The values a `for` iterator runs through (structural)."""
    return eval_arrays.iteration_values(expr, scope, evaluate)


def _unary(expr: ast.UnaryOp, scope: EvalScope, mode: Mode) -> Any:
    value = evaluate(expr.operand, scope, mode)
    if expr.op in ("!", "not"):
        return sympy.Not(to_bool(value, expr.span))
    value = numeric(value, expr.span)
    return -value if expr.op == "-" else value


# Left-associated chains of one family: evaluated in a loop, not by recursing down the left operand.
_CHAIN_FAMILIES = (frozenset({"+", "-", ".+", ".-"}), frozenset({"*", "/", ".*", "./"}),
                   frozenset({"and", "&&"}), frozenset({"or", "||"}))


def _binary(expr: ast.BinaryOp, scope: EvalScope, mode: Mode) -> Any:
    op = expr.op
    for family in _CHAIN_FAMILIES:
        if op in family and isinstance(expr.left, ast.BinaryOp) and expr.left.op in family:
            return _chain(expr, family, scope, mode)
    if op in INTEGER_OPERATORS:
        return integer_operator(op, evaluate(expr.left, scope, mode),
                                 evaluate(expr.right, scope, mode), expr.span)
    left = evaluate(expr.left, scope, mode)
    right = evaluate(expr.right, scope, mode)
    if op in ("and", "or", "&&", "||"):
        a, b = to_bool(left, expr.span), to_bool(right, expr.span)
        return sympy.And(a, b) if op in ("and", "&&") else sympy.Or(a, b)
    if op in COMPARISONS:
        if is_array(left) or is_array(right):
            raise DyadError(f"comparison `{op}` needs scalars", expr.span)
        if isinstance(left, str) or isinstance(right, str):
            if op not in ("==", "!="):
                raise DyadError(f"strings cannot be compared with `{op}`", expr.span)
            equal = left == right
            return sympy.true if equal == (op == "==") else sympy.false
        return COMPARISONS[op](numeric(left, expr.span), numeric(right, expr.span))
    left, right = numeric(left, expr.span), numeric(right, expr.span)
    try:
        return arith(op, left, right, expr.span)
    except TypeError as exc:
        raise DyadError(f"invalid operands for `{op}`: {exc}", expr.span) from exc


def _chain(expr: ast.BinaryOp, family: frozenset, scope: EvalScope, mode: Mode) -> Any:
    """`a + b - c + ...` (a 20000-term sum is a 20000-deep left chain): one loop, and for
    scalars one flat sympy Add or Mul instead of re-flattening a growing sum at every term."""
    first, links = ast.left_chain(expr, family)
    if "and" in family or "or" in family:
        conditions = [to_bool(evaluate(first, scope, mode), expr.span)]
        conditions += [to_bool(evaluate(link.right, scope, mode), link.span) for link in links]
        return sympy.And(*conditions) if "and" in family else sympy.Or(*conditions)
    values = [numeric(evaluate(first, scope, mode), expr.span)]
    values += [numeric(evaluate(link.right, scope, mode), link.span) for link in links]
    if not any(is_array(v) for v in values):
        if "+" in family:
            return sympy.Add(values[0], *(v if link.op in ("+", ".+") else -v
                                          for link, v in zip(links, values[1:])))
        return sympy.Mul(values[0], *(v if link.op in ("*", ".*") else sympy.Pow(v, -1)
                                      for link, v in zip(links, values[1:])))
    result = values[0]
    for link, value in zip(links, values[1:]):
        try:
            result = arith(link.op, result, value, link.span)
        except TypeError as exc:
            raise DyadError(f"invalid operands for `{link.op}`: {exc}", link.span) from exc
    return result


def _if(expr: ast.IfExpr, scope: EvalScope, mode: Mode) -> Any:
    cond = to_bool(evaluate(expr.condition, scope, mode), expr.span)
    if cond is sympy.true:
        return evaluate(expr.then, scope, mode)
    if cond is sympy.false:
        return evaluate(expr.otherwise, scope, mode)
    return piecewise(cond, numeric(evaluate(expr.then, scope, mode), expr.span),
                      numeric(evaluate(expr.otherwise, scope, mode), expr.span), expr.span)


def _call(expr: ast.Call, scope: EvalScope, mode: Mode) -> Any:
    name, span = expr.function, expr.span
    entry = builtin(name)
    if entry is not None and entry.form is not None:
        return entry.form(expr, scope, mode, evaluate)
    if entry is not None:
        name = entry.name           # an alias: Julia's `maximum` is `max`
    lex = scope.lexical
    if "." in name:                 # `Gear.High()`: an enum member written as a constructor
        member = enum_member_value(name, lex, span)
        if member is not None:
            check_member_call(expr, lex)
            return member
    if mode is Mode.SYMBOLIC:       # a function of a Julia object (compiler/model/object_calls.py)
        value = object_calls.object_call(expr, scope, object_calls.Evaluator(
            value=lambda arg, at: numeric(evaluate(arg, at, mode), span),
            structural=lambda arg, at: evaluate(arg, at, Mode.STRUCTURAL),
            inline=lambda function, args: _julia_call(function, args, expr, scope, mode)))
        if value is not None:
            return value
    impl = lex.library.resolve_function(name, lex.package, lex.file, span)
    args = [numeric(evaluate(a, scope, mode), span) for a in expr.args]
    if not isinstance(impl, FunctionImpl):      # a function read from Julia source
        return _julia_call(impl, args, expr, scope, mode)
    kwargs = {k.name: numeric(evaluate(k.value, scope, mode), span) for k in expr.kwargs}
    try:
        return impl(args, kwargs)
    except FunctionCallError as exc:
        raise DyadError(str(exc), span) from exc
    except TypeError as exc:
        raise DyadError(f"bad arguments for `{name}`: {exc}", span) from exc


def switch_branch(relation: ast.Switch | ast.SwitchValue, scope: EvalScope
                  ) -> tuple[tuple, EvalScope]:
    """The relations (or, of a switch value, the one value) of the case of `switch subject` that
    the subject's structural value selects (its `else` when no case names it), and the scope to
    read them in: `scope` with the fields a case such as `case InitialState(x0)` binds."""
    value = structural_int(evaluate(relation.subject, scope, Mode.STRUCTURAL), relation.span,
                           "a switch subject")
    case, member = selected_case(relation, scope, value)
    if case is None:
        return relation.otherwise, scope
    bound = case_bindings(relation, case, member, scope, evaluate)
    return case.body, scope.bind(**bound) if bound else scope


def _switch_value(expr: ast.SwitchValue, scope: EvalScope, mode: Mode) -> Any:
    chosen, chosen_scope = switch_branch(expr, scope)
    if not chosen:
        raise DyadError("no case of this `switch` names the value of its subject, and it has no "
                        "`else`", expr.span, hint="add a case for every member, or an `else` value")
    return evaluate(chosen[0], chosen_scope, mode)


def _julia_call(function: Any, args: list, expr: ast.Call, scope: EvalScope, mode: Mode) -> Any:
    """Inline a function read from a package's Julia source (compiler/julia/inline.py)."""
    return object_calls.inline(function, args, expr, scope,
                               lambda body, inner: evaluate(body, inner, mode))


def _range(expr: ast.Range, scope: EvalScope, mode: Mode) -> Any:
    return eval_arrays.range_value(expr, scope, mode, evaluate)


def _array_literal(expr: ast.ArrayLit, scope: EvalScope, mode: Mode) -> Any:
    return eval_arrays.array_literal(expr, scope, mode, evaluate)


def _comprehension(expr: ast.Comprehension, scope: EvalScope, mode: Mode) -> Any:
    return eval_arrays.comprehension(expr, scope, mode, evaluate)


_HANDLERS = {
    ast.Number: _number, ast.String: _string, ast.Boolean: _boolean, ast.End: _end,
    ast.Colon: _colon, ast.Ref: _ref, ast.Range: _range, ast.UnaryOp: _unary,
    ast.BinaryOp: _binary, ast.IfExpr: _if, ast.ArrayLit: _array_literal,
    ast.Comprehension: _comprehension, ast.Call: _call, ast.SwitchValue: _switch_value,
}
