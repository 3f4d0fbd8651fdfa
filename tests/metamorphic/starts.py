"""A consistent start given as a guess <-> as an `initial` equation: the rewrite that needs to
know the model's solution at the start and whether its initial system is determined, so it takes
them from the base's run (a StartContext) instead of from the syntax alone.

- guess -> initial: `x::Real(guess = c)` or `guess x = c` becomes `initial x = c` where c is the
  value the base starts x at (to 1e-10 relative): one more, consistent, initial condition.
- initial -> guess: `initial x = c` becomes `guess x = c` where the initial system stays
  determined without it: the compiled variant fixes the same unknowns at their start values as
  the base (`reduced.initial.chosen`), none more.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Callable

from compiler.syntax import ast
from tests.metamorphic import walk
from tests.metamorphic.forms import Rewrite, declarations_by_name

CONSISTENT = 1e-10      # |guess - start| / max(1, |start|) below which a guess is the start itself


@dataclass(frozen=True)
class StartContext:
    starts: dict[str, float]                              # the base's value at the start, per variable
    determined: Callable[[ast.ComponentDef], bool]        # the variant's initial system as determined as the base's


def _number(expr) -> float | None:
    if isinstance(expr, ast.Number) and not isinstance(expr.value, bool):
        return float(expr.value)
    if isinstance(expr, ast.UnaryOp) and expr.op == "-":
        inner = _number(expr.operand)
        return None if inner is None else -inner
    return None


def _scalar_ref(ref) -> str | None:
    if isinstance(ref, ast.Ref) and len(ref.parts) == 1 and not ref.parts[0].indices:
        return ref.parts[0].name
    return None


def _initial_names(component) -> set[str]:
    names = {d.name for d in component.declarations if isinstance(d, ast.VariableDecl) and d.initial is not None}
    for r in component.relations:
        if isinstance(r, ast.Equation) and r.initial:
            names.update(n.parts[0].name for n in walk.nodes(r) if isinstance(n, ast.Ref))
    return names


def _guesses(component) -> list[tuple[str, object, object]]:
    """(name, value expression, where) of each numeric guess of a declared scalar variable:
    `where` is the declaration or the Guess relation that gives it."""
    found = []
    for d in component.declarations:
        if isinstance(d, ast.VariableDecl) and not d.type.dims:
            for m in d.type.modifications:
                if m.name == "guess" and not m.nested and _number(m.value) is not None:
                    found.append((d.name, m.value, d))
    declared = declarations_by_name(component)
    for r in component.relations:
        name = _scalar_ref(r.target) if isinstance(r, ast.Guess) else None
        if name in declared and _number(r.value) is not None:
            found.append((name, r.value, r))
    return found


def guess_to_initial(component, name, value_expr, where):
    """The guess of `name` (in the declaration or the Guess relation `where`) dropped, and
    `initial name = value_expr` added."""
    relations = [r for r in component.relations if r is not where]
    declarations = list(component.declarations)
    if isinstance(where, ast.VariableDecl):
        kept = tuple(m for m in where.type.modifications if m.name != "guess")
        declarations = [dataclasses.replace(d, type=dataclasses.replace(d.type, modifications=kept)) if d is where else d
                        for d in declarations]
    relations.append(ast.Equation(ast.Ref((ast.RefPart(name),)), value_expr, initial=True))
    return dataclasses.replace(component, relations=tuple(relations), declarations=tuple(declarations))


def initial_to_guess(component, index):
    r = component.relations[index]
    relations = list(component.relations)
    relations[index] = ast.Guess(r.lhs, r.rhs)
    return dataclasses.replace(component, relations=tuple(relations))


def initial_and_guess(component, rng, context: StartContext) -> Rewrite | None:
    """One consistent start moved between its guess and its `initial` form (module doc), drawn
    among those whose move keeps the model's solution, and half of the time then another start
    the other way (a guess made an initial condition lets another initial condition become a
    guess: Andrews' crank angle given by a dependent angle); None where no start moves."""
    first = _one_move(component, rng, context, guesses=True, initials=True)
    if first is None:
        return None
    if rng.random() < 0.5:
        second = _one_move(first, rng, context, guesses=False, initials=True, keep=_initial_names(first) - _initial_names(component))
        if second is not None:
            return Rewrite(second)
    return Rewrite(first)


def _one_move(component, rng, context, *, guesses: bool, initials: bool, keep=frozenset()):
    taken = _initial_names(component)
    options = []
    for name, value, where in _guesses(component) if guesses else ():
        start = context.starts.get(name)
        if name not in taken and start is not None and abs(_number(value) - start) <= CONSISTENT * max(1.0, abs(start)):
            options.append(lambda name=name, value=value, where=where: guess_to_initial(component, name, value, where))
    for i, r in enumerate(component.relations) if initials else ():
        if isinstance(r, ast.Equation) and r.initial and _scalar_ref(r.lhs) not in (None, *keep) \
                and _number(r.rhs) is not None:
            options.append(lambda i=i: initial_to_guess(component, i))
    rng.shuffle(options)
    for make in options[:3]:                 # each check compiles the candidate
        candidate = make()
        if context.determined(candidate):
            return candidate
    return None
