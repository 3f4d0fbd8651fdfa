"""Rewrites of numbers, parameters and equations: literal kinds, parameters inlined or named,
sides swapped, terms moved, one side, both sides scaled. Each (component, rng) -> Rewrite or None."""
from __future__ import annotations

import dataclasses

from compiler.syntax import ast
from tests.metamorphic import walk
from tests.metamorphic.forms import (Rewrite, binary, fresh, is_scalar, number, pick, top_level_equations,
                                     with_relation)

# ------------------------------------------------------------------------ numbers and parameters

def literal_kinds(component, rng):
    """Integer <-> real literals: `6` -> `6.0` or `6e0`, `2.0` -> `2`, in equations and
    parameter values (never in indices, sizes or ranges)."""
    changed = [False]

    def swap(node):
        if not isinstance(node, ast.Number) or isinstance(node.value, bool) or rng.random() < 0.3:
            return node
        value = node.value
        if isinstance(value, int):
            changed[0] = True
            return ast.Number(float(value), text=rng.choice([f"{value}.0", f"{value}e0"]))
        if float(value).is_integer() and abs(value) < 1e15:
            changed[0] = True
            return ast.Number(int(value), text=str(int(value)))
        return node
    relations = tuple(walk.transform(r, swap, walk.arithmetic) if isinstance(r, ast.Equation) else r
                      for r in component.relations)
    declarations = tuple(dataclasses.replace(d, default=walk.transform(d.default, swap, walk.arithmetic))
                         if isinstance(d, ast.ParameterDecl) and d.default is not None and not d.type.dims
                         and d.variability == "parameter" else d for d in component.declarations)
    new = dataclasses.replace(component, relations=relations, declarations=declarations)
    return Rewrite(new) if changed[0] else None


def inline_parameters(component, rng):
    """A parameter with a literal value written as that literal in the equations."""
    candidates = [d for d in component.declarations
                  if isinstance(d, ast.ParameterDecl) and isinstance(d.default, ast.Number)
                  and d.variability == "parameter" and not d.type.dims
                  and any(walk.refs_to(r, d.name) for r in component.relations if isinstance(r, ast.Equation))]
    if not candidates:
        return None
    relations = component.relations
    for declaration in pick(rng, candidates):
        value = declaration.default
        relations = tuple(walk.replace_ref(r, declaration.name, value) if isinstance(r, ast.Equation) else r
                          for r in relations)
    return Rewrite(dataclasses.replace(component, relations=relations))


def name_literals(component, rng):
    """Literals of the equations (not exponents, indices) given a name: `parameter mm_p1 = 4530.0`."""
    declarations, counter = list(component.declarations), [0]

    def lift(node):
        changes = {}
        for key in ("left", "right", "operand", "lhs", "rhs"):
            child = getattr(node, key, None)
            if isinstance(child, ast.Number) and not isinstance(child.value, bool) and rng.random() < 0.4 \
                    and not (key == "right" and getattr(node, "op", None) == "^"):
                counter[0] += 1
                parameter = fresh(dataclasses.replace(component, declarations=tuple(declarations)), "p")
                declarations.append(ast.ParameterDecl(parameter, ast.TypeSpec("Real"), child))
                changes[key] = ast.Ref((ast.RefPart(parameter),))
        return dataclasses.replace(node, **changes) if changes else node
    relations = tuple(walk.transform(r, lift, walk.arithmetic) if isinstance(r, ast.Equation) and not r.initial
                      else r for r in component.relations)
    if not counter[0]:
        return None
    return Rewrite(dataclasses.replace(component, relations=relations, declarations=tuple(declarations)))


# ---------------------------------------------------------------------------- equation algebra

def swap_sides(component, rng):
    """`a = b` -> `b = a`."""
    indices = pick(rng, top_level_equations(component))
    for i in indices:
        r = component.relations[i]
        component = with_relation(component, i, dataclasses.replace(r, lhs=r.rhs, rhs=r.lhs))
    return Rewrite(component) if indices else None


def _movable(expr):
    return isinstance(expr, ast.BinaryOp) and expr.op in ("+", "-")


def move_terms(component, rng):
    """A term moved across `=`: `a = b + c` -> `a - c = b`, `a = b - c` -> `a + c = b`."""
    candidates = [i for i in top_level_equations(component) if _movable(component.relations[i].rhs)]
    indices = pick(rng, candidates)
    for i in indices:
        r = component.relations[i]
        back = "-" if r.rhs.op == "+" else "+"
        component = with_relation(component, i, dataclasses.replace(
            r, lhs=binary(back, r.lhs, r.rhs.right), rhs=r.rhs.left))
    return Rewrite(component) if indices else None


def one_side(component, rng):
    """All terms on one side: `a = b` -> `a - b = 0` or `0 = b - a`. Only scalar equations (one
    side certainly scalar): an array equation's `0` would need the array's size."""
    indices = pick(rng, [i for i in top_level_equations(component)
                         if is_scalar(component.relations[i].lhs, component)
                         or is_scalar(component.relations[i].rhs, component)])
    for i in indices:
        r = component.relations[i]
        if rng.random() < 0.5:
            new = dataclasses.replace(r, lhs=binary("-", r.lhs, r.rhs), rhs=number(0.0))
        else:
            new = dataclasses.replace(r, lhs=ast.Number(0, text="0"), rhs=binary("-", r.rhs, r.lhs))
        component = with_relation(component, i, new)
    return Rewrite(component) if indices else None


SCALES = (2.0, -3.0, 0.001, 1000.0, 7.25)


def scale_equations(component, rng):
    """Both sides times a nonzero constant, or times a new nonzero parameter `mm_scale`.
    Only scalar equations (a matrix equation times a number is still fine, but a scalar test
    keeps the rewrite's meaning obvious)."""
    candidates = [i for i in top_level_equations(component)
                  if is_scalar(component.relations[i].lhs, component) and is_scalar(component.relations[i].rhs, component)]
    indices = pick(rng, candidates)
    if not indices:
        return None
    by_parameter = rng.random() < 0.5
    factor = rng.choice(SCALES)
    declarations = component.declarations
    if by_parameter:
        name = fresh(component, "scale")
        declarations += (ast.ParameterDecl(name, ast.TypeSpec("Real"), number(factor)),)
        scale = ast.Ref((ast.RefPart(name),))
    else:
        scale = number(factor)
    for i in indices:
        r = component.relations[i]
        component = with_relation(component, i, dataclasses.replace(
            r, lhs=binary("*", scale, r.lhs), rhs=binary("*", scale, r.rhs)))
    return Rewrite(dataclasses.replace(component, declarations=declarations))
