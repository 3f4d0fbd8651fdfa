"""Where a model's equations are not smooth: the relations and kinks (if/ifelse conditions, abs,
min/max, sign, floor, mod) of the integrated system, sorted into

- time events: the condition depends on time and parameters only, so the times are known before
  the run, as offset + k * period with both sympy expressions of the parameters (a step at t0,
  a pulse's edges, a square wave); the runtime stops exactly there and restarts;
- state events: the condition depends on the unknowns; its zero function g (a relation a > b gives
  g = a - b) is watched by IDAS, which locates the crossing and restarts there.

This is what Modelica tools and ModelingToolkit's discontinuity detection do for Dyad; we keep the
relation itself in the equations (no locking), so between events the model is smooth and at an
event the restart sees the other branch.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy
from sympy.core.relational import Relational

from compiler.flat import TIME
from compiler.structure.reduced import ReducedSystem


@dataclass(frozen=True)
class TimeEvent:
    offset: sympy.Expr          # in the parameters
    period: sympy.Expr          # 0 for a single event
    label: str


@dataclass(frozen=True)
class StateEvent:
    zero: sympy.Expr            # in states, algebraics, assignment targets, parameters, time
    label: str


@dataclass(frozen=True)
class Events:
    time_events: tuple[TimeEvent, ...]
    state_events: tuple[StateEvent, ...]


def find_events(reduced: ReducedSystem) -> Events:
    """The time and state events of the equations that are integrated (ode, alg and the
    assignments they use); observables are evaluated after the run and need none."""
    time_only = _time_only_symbols(reduced)
    time_events: dict[tuple, TimeEvent] = {}
    state_events: dict[sympy.Expr, StateEvent] = {}
    expressions = list(reduced.ode) + list(reduced.alg) + [a.expr for a in reduced.assignments]
    for expr in expressions:
        for zero, label in _zero_functions(expr):
            if zero.free_symbols <= time_only:
                for event in _solve_for_time(zero, label):
                    time_events.setdefault((event.offset, event.period), event)
                continue
            if zero not in state_events and -zero not in state_events:
                state_events[zero] = StateEvent(zero, label)
    return Events(tuple(time_events.values()), tuple(state_events.values()))


def _time_only_symbols(reduced: ReducedSystem) -> set[sympy.Symbol]:
    known = {TIME} | {sympy.Symbol(q.name) for q in reduced.parameters}
    for a in reduced.assignments:               # in order: each uses only earlier targets
        if a.expr.free_symbols <= known:
            known.add(sympy.Symbol(a.target))
    return known


def _zero_functions(expr: sympy.Expr):
    """(g, label) for every non-smooth point of `expr`: g changes sign there."""
    seen = set()
    for node in sympy.preorder_traversal(expr):
        found = []
        if isinstance(node, Relational) and not isinstance(node, (sympy.Eq, sympy.Ne)):
            found.append((node.lhs - node.rhs, str(node)))
        elif isinstance(node, (sympy.Min, sympy.Max)) and len(node.args) == 2:
            found.append((node.args[0] - node.args[1], str(node)))
        elif isinstance(node, (sympy.Abs, sympy.sign, sympy.Heaviside)):
            found.append((node.args[0], str(node)))
        elif isinstance(node, (sympy.floor, sympy.ceiling)):
            found.append((sympy.sin(sympy.pi * node.args[0]), str(node)))
        elif isinstance(node, sympy.Mod):
            found.append((sympy.sin(sympy.pi * node.args[0] / node.args[1]), str(node)))
        for zero, label in found:
            zero = sympy.expand(zero) if zero.is_polynomial() else zero
            if zero.free_symbols and zero not in seen:
                seen.add(zero)
                yield zero, label


def _solve_for_time(zero: sympy.Expr, label: str) -> list[TimeEvent]:
    """The times where a time-only zero function changes sign: linear in time gives one event;
    sin(pi * a / m) (from mod and floor) with `a` linear in time gives a periodic one; a relation
    on mod(a, m) gives its crossings and the jumps of the mod. Anything else is left to IDAS."""
    if TIME not in zero.free_symbols:
        return []
    if zero.atoms(sympy.Mod):
        return _mod_events(zero, label)
    if isinstance(zero, sympy.sin):
        inner = zero.args[0] / sympy.pi                  # a / m: crossings where it is an integer
        rate = sympy.diff(inner, TIME)
        if TIME not in rate.free_symbols and rate != 0:
            return [TimeEvent(-inner.subs(TIME, 0) / rate, sympy.Abs(1 / rate), label)]
        return []
    slope = sympy.diff(zero, TIME)
    if TIME not in slope.free_symbols and slope != 0:
        return [TimeEvent(sympy.simplify(-zero.subs(TIME, 0) / slope), sympy.Integer(0), label)]
    return []


def _mod_events(zero: sympy.Expr, label: str) -> list[TimeEvent]:
    events = []
    for mod in zero.atoms(sympy.Mod):
        a, m = mod.args
        rate = sympy.diff(a, TIME)
        if TIME in rate.free_symbols or rate == 0 or TIME in m.free_symbols:
            return []
        level = sympy.Symbol("__mod_level")
        rest = zero.subs(mod, level)
        if TIME in rest.free_symbols or sympy.degree(rest, level) != 1:
            return []
        crossing = sympy.solve(rest, level)[0]         # mod(a, m) = crossing
        period = sympy.Abs(m / rate)
        events += [TimeEvent(-a.subs(TIME, 0) / rate, period, str(mod)),
                   TimeEvent((crossing - a.subs(TIME, 0)) / rate, period, label)]
    return events
