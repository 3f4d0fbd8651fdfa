"""Where a model's equations are not smooth: the relations and kinks (if/ifelse conditions, abs,
min/max, sign, floor, mod, a repeating table) of the integrated system, sorted into

- time events: the condition depends on time and parameters only, so the times are known before
  the run, as offset + k * period with both sympy expressions of the parameters (a step at t0,
  a pulse's edges, a square wave); the runtime stops exactly there and restarts;
- state events: the condition depends on the unknowns; its zero function g (a relation a > b gives
  g = a - b) is watched by IDAS, which locates the crossing and restarts there.

This is what Modelica tools and ModelingToolkit's discontinuity detection do for Dyad. Relations
on unknowns are locked between events (relation_locks.py): each keeps the value it had at the last
event, so IDAS's Newton iterations never see a condition flip, and the restart at an event takes
the other branch.
"""
from __future__ import annotations

import dataclasses
import itertools
from dataclasses import dataclass

import sympy
from sympy.core.relational import Relational

from compiler.model.flat import TIME
from compiler.model.interpolation import InterpolatedFunction
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
    timed_conditions: tuple[sympy.Expr, ...] = ()     # the nodes whose time events are known


# Inside a conditional whose switching times are known, time is read from this clock instead: the
# runtime sets it to the middle of the segment it integrates, so the condition holds its value over
# the whole segment, ends included (IDAS evaluates the last step at the segment's end, where the
# condition has already flipped). This is Modelica's relation locking between events.
EVENT_CLOCK = sympy.Symbol("__event_clock")


def lock_timed_conditions(reduced: ReducedSystem, events: Events) -> ReducedSystem:
    """`reduced` with every condition whose event times are known reading time from EVENT_CLOCK
    (values keep reading time: min(a, b) becomes `a if a' <= b' else b` with a', b' on the clock),
    and the clock added as the last (non-tunable) parameter."""
    if not events.timed_conditions:
        return reduced
    timed = set(events.timed_conditions)

    def lock(expr):
        return _locked(expr, timed) if expr.has(TIME) else expr

    from compiler.structure.reduced import Assignment, ParameterInfo
    return dataclasses.replace(
        reduced, ode=[lock(e) for e in reduced.ode], alg=[lock(e) for e in reduced.alg],
        assignments=[Assignment(a.target, lock(a.expr), a.origin) for a in reduced.assignments],
        observables=[Assignment(a.target, lock(a.expr), a.origin) for a in reduced.observables],
        parameters=list(reduced.parameters) + [ParameterInfo(EVENT_CLOCK.name, 0.0, None, False)])


def _locked(expr: sympy.Expr, timed: set) -> sympy.Expr:
    """Bottom-up: children first, then the node itself if its switching is timed."""
    if not expr.args or not expr.has(TIME):
        return expr
    rebuilt = expr.func(*[_locked(a, timed) for a in expr.args]) if not isinstance(expr, sympy.Piecewise) \
        else sympy.Piecewise(*[(_locked(e, timed), _locked(c, timed)) for e, c in expr.args])
    if expr not in timed:
        return rebuilt
    on_clock = lambda e: e.xreplace({TIME: EVENT_CLOCK})          # noqa: E731
    if isinstance(expr, Relational) or isinstance(expr, (sympy.sign, sympy.Heaviside, sympy.floor,
                                                         sympy.ceiling)):
        return on_clock(rebuilt)
    if isinstance(expr, (sympy.Min, sympy.Max)):
        a, b = rebuilt.args
        first = on_clock(a) <= on_clock(b) if isinstance(expr, sympy.Min) else on_clock(a) >= on_clock(b)
        return sympy.Piecewise((a, first), (b, True))
    if isinstance(expr, sympy.Abs):
        a = rebuilt.args[0]
        return sympy.Piecewise((a, on_clock(a) >= 0), (-a, True))
    if isinstance(expr, sympy.Mod):
        a, m = rebuilt.args
        return a - m * sympy.floor(on_clock(a) / m)
    if isinstance(expr, InterpolatedFunction) and len(expr.args) == 2:
        return rebuilt.func(rebuilt.args[0], on_clock(rebuilt.args[1]))     # the period, locked
    return rebuilt


def find_events(reduced: ReducedSystem) -> Events:
    """The time and state events of the equations that are integrated (ode, alg and the
    assignments they use); observables are evaluated after the run and need none."""
    time_only = _time_only_symbols(reduced)
    time_events: dict[tuple, TimeEvent] = {}
    state_events: dict[sympy.Expr, StateEvent] = {}
    timed: dict[sympy.Expr, None] = {}
    expressions = list(reduced.ode) + list(reduced.alg) + [a.expr for a in reduced.assignments]
    definitions = _time_only_definitions(reduced, time_only)
    for expr in expressions:
        for node, zero, label in _zero_functions(expr):
            if zero.free_symbols <= time_only:
                solved = _solve_for_time(_inline(zero, definitions), label)
                for event in solved:
                    time_events.setdefault((event.offset, event.period), event)
                if solved and not node.has(*_assignment_symbols(reduced)):
                    timed[node] = None
                if solved:
                    continue
                # a time-only condition whose times have no closed form here (Julia's rem with
                # its sign, sin(t) > 0.5): watched and located like a state event
            if zero not in state_events and -zero not in state_events:
                state_events[zero] = StateEvent(zero, label)
    return Events(tuple(time_events.values()), tuple(state_events.values()), tuple(timed))


def _time_only_definitions(reduced: ReducedSystem, time_only: set) -> list[tuple]:
    return [(sympy.Symbol(a.target), a.expr) for a in reduced.assignments
            if sympy.Symbol(a.target) in time_only]


def _inline(expr: sympy.Expr, definitions: list[tuple]) -> sympy.Expr:
    """`expr` in time and parameters only: time-only assignment targets replaced by their
    definitions (latest first, since each may use earlier ones)."""
    for symbol, definition in reversed(definitions):
        if expr.has(symbol):
            expr = expr.xreplace({symbol: definition})
    return expr


def _assignment_symbols(reduced: ReducedSystem) -> list[sympy.Symbol]:
    return [sympy.Symbol(a.target) for a in reduced.assignments] or [sympy.Symbol("__none")]


def _time_only_symbols(reduced: ReducedSystem) -> set[sympy.Symbol]:
    known = {TIME} | {sympy.Symbol(q.name) for q in reduced.parameters}
    for a in reduced.assignments:               # in order: each uses only earlier targets
        if a.expr.free_symbols <= known:
            known.add(sympy.Symbol(a.target))
    return known


def _zero_functions(expr: sympy.Expr):
    """(node, g, label) for every non-smooth node of `expr`: g changes sign where it switches."""
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
        elif isinstance(node, InterpolatedFunction) and node.table.wrap is not None:
            wrap = node.table.wrap       # repeats at first + k * period: a jump or a corner there
            found.append((sympy.sin(sympy.pi * (node.args[-1] - sympy.Float(wrap.first))
                                    / sympy.Float(wrap.period)), f"{type(node).__name__} repeats"))
        for zero, label in found:
            zero = _canonical(zero)
            if zero.free_symbols and zero not in seen:
                seen.add(zero)
                yield node, zero, label


def _canonical(zero: sympy.Expr) -> sympy.Expr:
    return sympy.expand(zero) if zero.is_polynomial() else zero


def relation_zero(node: Relational) -> sympy.Expr:
    """The zero function watched for the relation `node` (a > b: a - b), as find_events writes it."""
    return _canonical(node.lhs - node.rhs)


def _solve_for_time(zero: sympy.Expr, label: str) -> list[TimeEvent]:
    """The times where a time-only zero function changes sign: linear in time gives one event;
    sin(pi * a / m) (from mod and floor) with `a` linear in time gives a periodic one; a relation
    on mod(a, m) gives its crossings and the jumps of the mod. Anything else is left to IDAS."""
    if TIME not in zero.free_symbols:
        return []
    kinks = [a for a in zero.atoms(sympy.Min, sympy.Max, sympy.Abs) if a.has(TIME)]
    if kinks:
        # min(a, b) is a or b, |a| is a or -a: the crossings are among those of every branch
        # (a few extra segment ends cost little; a missed one would step over the kink)
        branches = [list(k.args) if not isinstance(k, sympy.Abs) else [k.args[0], -k.args[0]]
                    for k in kinks]
        if len(kinks) > 4:
            return []
        events = []
        for choice in itertools.product(*branches):
            found = _solve_for_time(zero.xreplace(dict(zip(kinks, choice))), label)
            if not found and any(TIME in c.free_symbols for c in choice):
                return []
            events += found
        return events
    zero = zero.replace(sympy.floor, lambda a: a - sympy.Mod(a, 1)).replace(
        sympy.ceiling, lambda a: a + sympy.Mod(-a, 1))
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
        # cancel, not simplify: the same time for rational expressions (the excavator's clamps),
        # without simplify's import of sympy.physics.units (0.1 s of a cold run)
        return [TimeEvent(sympy.cancel(-zero.subs(TIME, 0) / slope), sympy.Integer(0), label)]
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
