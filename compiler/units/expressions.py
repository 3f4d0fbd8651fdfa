"""The unit of an AST expression in an instance scope: a Dim (constraints.py), FREE for a bare
literal, None when it cannot be known (a Julia function's result). Every place where two units
must agree (the terms of a sum, the branches of an `if`, the sides of a comparison, the elements
of an array, the arguments of min/max) becomes a constraint with the term's source span; the
arguments of exp, log, sin, ... must be dimensionless; der(x) has x's unit per second.
"""
from __future__ import annotations

from fractions import Fraction
from typing import Any, Callable

import numpy as np

from compiler.errors import DyadError
from compiler.model.expressions import EvalScope, Mode, apply_indices, evaluate, is_node_like, \
    switch_branch, \
    iteration_values
from compiler.model.instantiate import ParameterInstance, VariableInstance
from compiler.syntax import ast
from compiler.units.constraints import DIMENSIONLESS, FREE, Dim, Site
from compiler.units.quantity import SECOND

SECONDS = Dim(SECOND, (), "s")
DIMENSIONLESS_ARGUMENTS = {"sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh",
                           "exp", "log", "log10", "log2", "asinh", "acosh", "atanh"}
SAME_UNIT = {"abs", "floor", "ceil", "round", "trunc", "identity", "transpose", "sum", "norm",
             "noEvent", "pre", "smooth", "fill", "hcat", "vcat", "first", "last"}
AGREEING = {"min", "max", "minimum", "maximum", "clamp", "mod", "rem", "hypot"}
PURE_NUMBERS = {"sign", "size", "length", "zeros", "ones", "div", "initial", "not", "integer"}
DECLARATIONS = (ParameterInstance, VariableInstance)
SUM_OPS = frozenset({"+", "-", ".+", ".-"})
PRODUCT_OPS = frozenset({"*", "/", ".*", "./"})
COMPARISONS = frozenset({"<", "<=", ">", ">=", "==", "!="})
LOGICAL = frozenset({"and", "or", "&&", "||"})


class ExpressionUnits:
    """Units of expressions for one check: `declared(target)` gives the Dim of a parameter or
    variable instance, `require(left, right, site)` records a constraint."""

    def __init__(self, declared: Callable[[Any, Any], Any], require: Callable[[Any, Any, Site], None]):
        self.declared = declared
        self.require = require
        self.path, self.instance = "", None

    def at(self, node: Any) -> None:
        """The instance whose relations are checked next (named in messages)."""
        self.path, self.instance = node.path, node.decl_span

    def site(self, kind: str, term: Any, other: Any, labels: tuple[str, str],
             statement: Any = None) -> Site:
        return Site(kind, getattr(term, "span", None), getattr(other, "span", None), labels,
                    self.path, self.instance, statement)

    # -------------------------------------------------------------------------------- terms

    def of(self, expr: Any, scope: EvalScope) -> Any:
        kind = type(expr)
        if kind is ast.Ref:
            return self.ref(expr, scope)
        if kind is ast.Number or kind is ast.End or kind is ast.Colon:
            return FREE
        if kind is ast.BinaryOp:
            return self.binary(expr, scope)
        if kind is ast.UnaryOp:
            inner = self.of(expr.operand, scope)
            return FREE if expr.op in ("!", "not") else inner
        if kind is ast.Call:
            return self.call(expr, scope)
        if kind is ast.IfExpr:
            self.of(expr.condition, scope)
            return self.agreeing([expr.then, expr.otherwise], scope, "branch",
                                 ("the `else` branch", "the `then` branch"))
        if kind is ast.ArrayLit:
            return self.agreeing(list(expr.elements), scope, "array", ("this element", "first element"))
        if kind is ast.Range:
            parts = [expr.start, expr.stop] + ([expr.step] if expr.step is not None else [])
            return self.agreeing(parts, scope, "range", ("this bound", "first bound"))
        if kind is ast.Comprehension:
            return self.comprehension(expr, scope)
        if kind is ast.Boolean:
            return FREE
        if kind is ast.SwitchValue:     # the unit of the value the subject selects
            chosen, chosen_scope = switch_branch(expr, scope)
            return self.of(chosen[0], chosen_scope) if chosen else None
        return None                     # strings

    def ref(self, ref: ast.Ref, scope: EvalScope) -> Any:
        target = self.target(ref, scope)
        if type(target) in DECLARATIONS:
            return self.declared(target, ref)
        return target if target is None or target is FREE or type(target) is Dim else None

    def target(self, ref: ast.Ref, scope: EvalScope) -> Any:
        """The parameter or variable instance (or node) `ref` names; FREE for a loop variable,
        an enum member or pi; the Dim of `time`; None when it cannot be followed."""
        first = ref.parts[0]
        if first.name in scope.bindings:
            return FREE
        current = _member(scope.node, first.name)
        if current is None:
            if first.name == "time" and len(ref.parts) == 1:
                return SECONDS
            return FREE if first.name in ("pi", "π", "Inf") or len(ref.parts) > 1 else None
        for index, part in enumerate(ref.parts[1:]):
            if isinstance(current, np.ndarray) and ref.parts[index].indices:
                current = self.indexed(current, ref.parts[index], scope, ref)
            if not is_node_like(current):
                return None
            current = _member(current, part.name)
            if current is None:
                return None
        last = ref.parts[-1]
        if isinstance(current, np.ndarray) and last.indices:
            current = self.indexed(current, last, scope, ref)
        return current

    def indexed(self, nodes: np.ndarray, part: ast.RefPart, scope: EvalScope, ref: ast.Ref) -> Any:
        try:
            return apply_indices(nodes, part.indices, part.name, scope, ref.span)
        except DyadError:
            return None

    # -------------------------------------------------------------------------- operators

    def binary(self, expr: ast.BinaryOp, scope: EvalScope) -> Any:
        op = expr.op
        if op in SUM_OPS:
            first, links = ast.left_chain(expr, SUM_OPS)
            return self.sum([first] + [link.right for link in links], scope)
        if op in PRODUCT_OPS:
            first, links = ast.left_chain(expr, PRODUCT_OPS)
            result = self.of(first, scope)
            for link in links:          # a literal factor takes the unit the product needs
                right = self.of(link.right, scope)
                if result is None or right is None:
                    result = None
                elif result is FREE or right is FREE:
                    result = FREE
                elif link.op in ("*", ".*"):
                    result = result * right
                else:
                    result = result / right
            return result
        if op in ("^", ".^"):
            return self.power(expr, scope)
        if op in COMPARISONS:
            self.agreeing([expr.left, expr.right], scope, "comparison",
                          ("the right side", "the left side"))
            return FREE
        if op in LOGICAL:               # a chain walked as a list: 2000 `and`s nest 2000 deep
            first, links = ast.left_chain(expr, LOGICAL)
            for operand in [first] + [link.right for link in links]:
                self.of(operand, scope)
            return FREE
        if op in ("%", "÷"):
            return self.agreeing([expr.left, expr.right], scope, "argument",
                                 ("the divisor", "the dividend"))
        return None

    def sum(self, terms: list, scope: EvalScope) -> Any:
        return self.agreeing(terms, scope, "sum", ("this term", "first term"))

    def agreeing(self, exprs: list, scope: EvalScope, kind: str, labels: tuple[str, str]) -> Any:
        """The one unit of `exprs`, each constrained to the first that has one."""
        reference, reference_expr, unknown = None, None, False
        for expr in exprs:
            unit = self.of(expr, scope)
            if unit is None:
                unknown = True
            elif unit is not FREE:
                if reference is None:
                    reference, reference_expr = unit, expr
                else:
                    self.require(reference, unit, self.site(kind, expr, reference_expr, labels))
        if reference is not None:
            return reference
        return None if unknown else FREE

    def power(self, expr: ast.BinaryOp, scope: EvalScope) -> Any:
        base = self.of(expr.left, scope)
        exponent = _constant_exponent(expr.right, scope)
        if exponent is None:            # a parameter or variable exponent: dimensionless
            self.require(DIMENSIONLESS, _factor(self.of(expr.right, scope)),
                         self.site("exponent", expr.right, None, ("the exponent", "")))
            if not self.varies(expr.right, scope):
                return None             # Bekker's `d ^ n`: its unit follows the value of n
            self.require(DIMENSIONLESS, _factor(base),
                         self.site("base", expr.left, None, ("the base", "")))
            return DIMENSIONLESS
        return base if base is None or base is FREE else base ** exponent

    def varies(self, expr: Any, scope: EvalScope) -> bool:
        """Whether `expr` names a variable or `time` (else it is constant during a run)."""
        if isinstance(expr, ast.Ref):
            target = self.target(expr, scope)
            return target is SECONDS or type(target) is VariableInstance
        children = {ast.BinaryOp: lambda e: (e.left, e.right), ast.UnaryOp: lambda e: (e.operand,),
                    ast.Call: lambda e: e.args, ast.IfExpr: lambda e: (e.condition, e.then, e.otherwise),
                    ast.SwitchValue: lambda e: tuple(c.body[0] for c in e.cases) + e.otherwise}
        inner = children.get(type(expr))
        return inner is not None and any(self.varies(e, scope) for e in inner(expr))

    # ------------------------------------------------------------------------------ calls

    def call(self, expr: ast.Call, scope: EvalScope) -> Any:
        name, args = expr.function, expr.args
        if name in ("der", "D") and len(args) == 1:
            inner = self.of(args[0], scope)
            return inner if inner is None or inner is FREE else inner / SECONDS
        if name == "ifelse" and len(args) == 3:
            self.of(args[0], scope)
            return self.agreeing([args[1], args[2]], scope, "branch",
                                 ("the `else` value", "the `then` value"))
        if name in DIMENSIONLESS_ARGUMENTS and len(args) == 1:
            self.require(DIMENSIONLESS, _factor(self.of(args[0], scope)),
                         self.site("argument", args[0], None, (f"the argument of `{name}`", "")))
            return DIMENSIONLESS
        if name == "atan2" and len(args) == 2:
            self.agreeing(list(args), scope, "argument", ("the second argument", "the first argument"))
            return DIMENSIONLESS
        if name == "sqrt" and len(args) == 1:
            inner = self.of(args[0], scope)
            return inner if inner is None or inner is FREE else inner ** Fraction(1, 2)
        if name in AGREEING:
            return self.agreeing(list(args), scope, "argument", ("this argument", "first argument"))
        if name in SAME_UNIT and args:
            for arg in args[1:]:
                self.of(arg, scope)
            return self.of(args[0], scope)
        for arg in args:
            self.of(arg, scope)
        for keyword in expr.kwargs:
            self.of(keyword.value, scope)
        if name in PURE_NUMBERS:
            return FREE
        if name in ("dot", "cross") and len(args) == 2:
            left, right = self.of(args[0], scope), self.of(args[1], scope)
            if left is None or right is None or left is FREE or right is FREE:
                return None if left is None or right is None else FREE
            return left * right
        return None                     # a library or Julia function: its unit is not declared

    def comprehension(self, expr: ast.Comprehension, scope: EvalScope) -> Any:
        """The unit of the element at every iterator's first value (all elements share it)."""
        inner = scope
        for iterator in (it for clause in expr.clauses for it in clause.iterators):
            try:
                first = iteration_values(iterator.iterable, inner)
            except DyadError:
                return None
            if not first:
                return FREE
            inner = inner.bind(**{iterator.variable: first[0]})
        return self.of(expr.expr, inner)


def _member(node: Any, name: str) -> Any:
    found = node.parameters.get(name)
    if found is None:
        found = node.variables.get(name)
    if found is None:
        found = node.children.get(name)
    return found


def _factor(unit: Any) -> Any:
    """A literal where a dimensionless value is required is a pure number."""
    return DIMENSIONLESS if unit is FREE else unit


def _constant_exponent(expr: Any, scope: EvalScope) -> int | Fraction | None:
    """The exponent when it is written as a number (`2`, `-1`, `0.5`, `1/3`), else None."""
    if type(expr) is ast.Number and type(expr.value) is int:
        return expr.value
    if not _literal_only(expr):
        return None
    try:
        value = float(evaluate(expr, scope, Mode.NUMERIC))
    except (DyadError, TypeError, ValueError):
        return None
    if value == int(value):
        return int(value)
    exact = Fraction(value).limit_denominator(1000)
    return exact if abs(float(exact) - value) <= 1e-12 * max(1.0, abs(value)) else None


def _literal_only(expr: Any) -> bool:
    if isinstance(expr, ast.Number):
        return True
    if isinstance(expr, ast.UnaryOp):
        return _literal_only(expr.operand)
    if isinstance(expr, ast.BinaryOp):
        return _literal_only(expr.left) and _literal_only(expr.right)
    return False
