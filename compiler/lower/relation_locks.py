"""Relations on unknowns locked between events, as Modelica specifies: inside the integrated
equations a relation such as `q > q_max` is read from a lock parameter that the runtime sets at
every event (compiler/runtime/relations.py) and holds over the IDAS call, so the equations IDAS
iterates on are smooth; the relation's zero function (events.py) is still watched, and where it
crosses the run restarts with the lock flipped.

Without the locks a condition that holds a state on its own switching surface (an op-amp's output
limiter: q_fp1 held at the supply voltage, the unsaturated branch driving it back with a gain of
1e5) flips between Newton iterations: IDAS took 20 million steps for 0.1 s, or failed.

A lock parameter holds 0 (false), 1 (true) or LIVE (2): the relation is evaluated as written. Its
default is LIVE, so that everything that does not set the locks (the initialization, a model
without states, an older caller) sees the equations as before.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import sympy

from compiler.lower.events import Events, relation_zero
from compiler.runtime.relations import LIVE
from compiler.structure.reduced import Assignment, ParameterInfo, ReducedSystem

LOCK_PREFIX = "__relation"
# what the relation is, given its watched zero function g times `sign`
_OPERATORS = {sympy.StrictGreaterThan: ">", sympy.GreaterThan: ">=",
              sympy.StrictLessThan: "<", sympy.LessThan: "<="}


@dataclass(frozen=True)
class RelationLock:
    parameter: str       # the lock parameter's name
    row: int             # the row of the model's `events` function watching this relation
    sign: int            # relation lhs - rhs = sign * that row
    operator: str        # ">", ">=", "<", "<="
    label: str

    def as_metadata(self) -> dict:
        return dataclasses.asdict(self)


def lock_state_relations(reduced: ReducedSystem, events: Events) -> tuple[ReducedSystem, list[RelationLock]]:
    """`reduced` with every relation of its integrated equations (ode, alg, assignments) whose zero
    function is a watched state event read through a lock parameter, and the locks (in the order
    of their parameters, appended last, not tunable). Observables keep their relations: they are
    evaluated after the run. A model without states has nothing to lock."""
    if not reduced.states or not events.state_events:
        return reduced, []
    rows = {}
    for i, event in enumerate(events.state_events):
        rows.setdefault(event.zero, (i, 1))
        rows.setdefault(-event.zero, (i, -1))
    expressions = list(reduced.ode) + list(reduced.alg) + [a.expr for a in reduced.assignments]
    locks: list[RelationLock] = []
    replacement: dict[sympy.Basic, sympy.Basic] = {}
    for expr in expressions:
        for node in sympy.preorder_traversal(expr):
            if type(node) not in _OPERATORS or node in replacement:
                continue
            found = rows.get(relation_zero(node))
            if found is None:             # a timed condition (event clock) or a constant one
                continue
            lock = sympy.Symbol(f"{LOCK_PREFIX}{len(locks)}")
            locks.append(RelationLock(lock.name, found[0], found[1], _OPERATORS[type(node)], str(node)))
            # LIVE (> 1.5): the relation itself; else the lock's value
            replacement[node] = sympy.ITE(lock > 1.5, node, lock > 0.5)
    if not locks:
        return reduced, []

    def locked(expr: sympy.Expr) -> sympy.Expr:
        return expr.xreplace(replacement) if expr.has(*replacement) else expr

    return dataclasses.replace(
        reduced, ode=[locked(e) for e in reduced.ode], alg=[locked(e) for e in reduced.alg],
        assignments=[Assignment(a.target, locked(a.expr), a.origin) for a in reduced.assignments],
        parameters=list(reduced.parameters) + [ParameterInfo(lock.parameter, LIVE, None, False)
                                               for lock in locks]), locks

