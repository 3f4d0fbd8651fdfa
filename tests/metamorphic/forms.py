"""What the metamorphic rewrites share: the Rewrite they return, fresh names, scalar tests and
equations the formatter prints so that the parser reads them back."""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from compiler.syntax import ast
from tests.metamorphic import walk

SCALAR_FUNCTIONS = frozenset({"sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh",
                              "tanh", "exp", "log", "sqrt", "abs", "der", "sign", "min", "max"})
PREFIX = "mm_"          # names the rewrites introduce (no model of the corpus uses it)


@dataclass(frozen=True)
class Rewrite:
    component: ast.ComponentDef
    renamed: dict[str, str] = field(default_factory=dict)      # new first name part -> old


# ------------------------------------------------------------------------------------- helpers

def top_level_equations(component):
    """Indices of the top-level equations (not inside loops or conditionals) of `component`."""
    return [i for i, r in enumerate(component.relations) if isinstance(r, ast.Equation)]


def leads_with_minus(expr) -> bool:
    while isinstance(expr, ast.BinaryOp):
        expr = expr.left
    return (isinstance(expr, ast.UnaryOp) and expr.op == "-") or \
        (isinstance(expr, ast.Number) and not isinstance(expr.value, bool) and expr.value < 0)


def printable(equation: ast.Equation) -> ast.Equation:
    """The equation with no unary minus leading its left side: the formatter prints `(-a) * b = c`
    as `-a * b = c`, which the parser reads as the continuation of the relation before (a bug of
    compiler/syntax/format.py, reported to the lead); `b = -a * c` or `0 = c - (-a) * b` instead."""
    if not leads_with_minus(equation.lhs):
        return equation
    if not leads_with_minus(equation.rhs):
        return dataclasses.replace(equation, lhs=equation.rhs, rhs=equation.lhs)
    return dataclasses.replace(equation, lhs=ast.Number(0, text="0"), rhs=binary("-", equation.rhs, equation.lhs))


def with_relation(component, index, relation):
    relations = list(component.relations)
    relations[index] = printable(relation) if isinstance(relation, ast.Equation) else relation
    return dataclasses.replace(component, relations=tuple(relations))


def pick(rng, items, share=0.5):
    """A random non-empty subset of `items` (about `share` of them), or [] if there are none."""
    if not items:
        return []
    chosen = [item for item in items if rng.random() < share]
    return chosen or [rng.choice(items)]


def fresh(component, stem: str) -> str:
    """A name `mm_<stem><k>` the component does not declare yet."""
    taken = {d.name for d in component.declarations}
    k = 1
    while f"{PREFIX}{stem}{k}" in taken:
        k += 1
    return f"{PREFIX}{stem}{k}"


def declarations_by_name(component):
    return {d.name: d for d in component.declarations}


def scalar_names(component) -> set[str]:
    """Parameters and variables the component declares, scalar (no array size)."""
    return {d.name for d in component.declarations
            if isinstance(d, (ast.ParameterDecl, ast.VariableDecl)) and not d.type.dims}


def array_names(component) -> set[str]:
    return {d.name for d in component.declarations
            if isinstance(d, (ast.ParameterDecl, ast.VariableDecl)) and d.type.dims}


def is_scalar(expr, component) -> bool:
    """Whether `expr` is certainly a scalar: references to declared scalars or constant-indexed
    elements of declared arrays, numbers, arithmetic and SCALAR_FUNCTIONS."""
    scalars, arrays = scalar_names(component), array_names(component)
    for node in walk.nodes(expr, walk.arithmetic):
        if isinstance(node, ast.Ref):
            part = node.parts[0]
            if len(node.parts) != 1:
                return False
            if part.name in arrays:
                if len(part.indices) != 1 or not isinstance(part.indices[0], ast.Number):
                    return False
            elif part.name not in scalars or part.indices:
                return False
        elif isinstance(node, ast.Call):
            if node.function not in SCALAR_FUNCTIONS or node.kwargs:
                return False
        elif isinstance(node, ast.BinaryOp):
            if node.op not in ("+", "-", "*", "/", "^"):
                return False
        elif not isinstance(node, (ast.Number, ast.UnaryOp)):
            return False
    return True


def number(value: float) -> ast.Number | ast.UnaryOp:
    if value < 0:
        return ast.UnaryOp("-", number(-value))
    return ast.Number(value, text=repr(float(value)))


def binary(op, left, right):
    return ast.BinaryOp(op, left, right)
