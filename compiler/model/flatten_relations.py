"""Flattening relations: equations (and `initial` ones, which also give start values), guesses,
connections (recorded for the connection sets), and the structural `for`, `if` and `switch`
relations, unrolled or resolved at compile time."""
from __future__ import annotations

from typing import Any

import sympy

from compiler.errors import DyadError
from compiler.model.expressions import EvalScope, Mode, evaluate, iteration_values, numeric, \
    shape_of, structural_bool, switch_branch
from compiler.model.flat import Equation, Origin
from compiler.model.flatten_state import FlattenState, scalars
from compiler.model.flatten_variables import set_numeric_attribute
from compiler.model.size_limits import check_elements
from compiler.syntax import ast


def relation_equations(state: FlattenState, relation: ast.Relation, scope: EvalScope) -> None:
    if isinstance(relation, ast.Equation):
        _equation(state, relation, scope)
    elif isinstance(relation, ast.Connect):
        state.graph.add(relation, scope)
    elif isinstance(relation, ast.Guess):
        _guess(state, relation, scope)
    elif isinstance(relation, ast.ForLoop):
        _for_loop(state, relation.iterators, relation.body, scope)
    elif isinstance(relation, ast.IfRelation):
        for branch in relation.branches:
            condition = evaluate(branch.condition, scope, Mode.STRUCTURAL)
            if structural_bool(condition, branch.span or relation.span):
                for inner in branch.body:
                    relation_equations(state, inner, scope)
                return
        for inner in relation.otherwise:
            relation_equations(state, inner, scope)
    elif isinstance(relation, ast.Switch):
        chosen, chosen_scope = switch_branch(relation, scope)
        for inner in chosen:
            relation_equations(state, inner, chosen_scope)
    elif isinstance(relation, ast.Continuity):
        pass        # relates `path` fields (a medium along a fluid path); implies no equation
    else:
        raise DyadError(f"unsupported relation {type(relation).__name__}",
                        getattr(relation, "span", None))


def _for_loop(state: FlattenState, iterators: tuple[ast.Iterator, ...],
              body: tuple[ast.Relation, ...], scope: EvalScope, outer: int = 1) -> None:
    if not iterators:
        for inner in body:
            relation_equations(state, inner, scope)
        return
    first, rest = iterators[0], iterators[1:]
    values = iteration_values(first.iterable, scope)
    # nested loops multiply: each range may be small, the unrolled body not
    check_elements(outer * len(values) * len(body), first.span, "this `for` loop")
    for value in values:
        _for_loop(state, rest, body, scope.bind(**{first.variable: value}), outer * len(values))


def _equation(state: FlattenState, relation: ast.Equation, scope: EvalScope) -> None:
    span = relation.span
    lhs = numeric(evaluate(relation.lhs, scope, Mode.SYMBOLIC), span)
    rhs = numeric(evaluate(relation.rhs, scope, Mode.SYMBOLIC), span)
    if shape_of(lhs) != shape_of(rhs):
        raise DyadError(f"array size mismatch in equation: left side has size "
                        f"{shape_of(lhs) or 'scalar'}, right side {shape_of(rhs) or 'scalar'}",
                        span)
    origin = Origin(scope.node.path, span)
    target = state.initial if relation.initial else state.equations
    for left, right in zip(scalars(lhs), scalars(rhs)):
        target.append(Equation(left - right, origin, "equation", relation.doc))
        if relation.initial:
            _start_from_initial_equation(state, left - right)


def _start_from_initial_equation(state: FlattenState, residual: Any) -> None:
    """An initial equation that fixes one unknown at a value gives that unknown its start value,
    however it is written: `x = 1.2`, `1.2 = x`, `x - 1.2 = 0` and `2 * x = 2.4` alike (the
    residual is linear in its only unknown, with coefficients known from the parameters). Taken
    only from `x = c` before, the other forms left the start at 0, where a mount's sqrt had no
    derivative and the initialization failed."""
    unknowns = [s for s in getattr(residual, "free_symbols", ()) if state.model.is_unknown(s.name)]
    if len(unknowns) != 1 or unknowns[0].name in state.model.derivatives:
        return
    (unknown,) = unknowns
    slope = sympy.diff(residual, unknown)
    if unknown in slope.free_symbols:
        return
    gain, offset = state.numeric_or_none(slope), state.numeric_or_none(residual.xreplace({unknown: 0}))
    if gain is not None and offset is not None and gain != 0.0:
        state.starts.setdefault(unknown.name, -offset / gain + 0.0)      # + 0.0: no -0.0


def _guess(state: FlattenState, relation: ast.Guess, scope: EvalScope) -> None:
    target = evaluate(relation.target, scope, Mode.SYMBOLIC)
    set_numeric_attribute(state, state.guesses, target, relation.value, scope, relation.span,
                                "guess")
