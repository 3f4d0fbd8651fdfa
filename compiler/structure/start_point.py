"""Values at the start for unknowns that have none, computed from the equations that give them
explicitly: the state choice at the start pivots on the constraints' Jacobian there, and an
unknown without a value otherwise counts as 0 (a road height `road_x = sqrt(L^2 - road_y^2)`
as 0 made the car axis's constraints singular at the start, and the choice fell back to names)."""
from __future__ import annotations

import math

import sympy

from compiler.model.flat import TIME, FlatSystem
from compiler.model.symbols import free_symbols
from compiler.structure.differentiate import partial
from compiler.structure.indexed import IndexedSystem


def completed_point(system: IndexedSystem, flat: FlatSystem, point: dict[str, float],
                    start_time: float = 0.0) -> dict[str, float]:
    """`point` plus every unknown that an equation linear in it determines from values already
    known (parameters, `time` = `start_time`, unknowns with a value), repeated until nothing new
    follows. Only finite results are kept; the equations are not solved as a system."""
    known = {sympy.Symbol(name): float(value) for name, value in point.items()}
    known.update({sympy.Symbol(p.name): float(p.value) for p in flat.parameters if isinstance(p.value, (int, float))})
    known[TIME] = float(start_time)
    changed = True
    while changed:
        changed = False
        for e, equation in enumerate(system.equations):
            missing = [system.symbols[v] for v in system.incidence[e] if system.symbols[v] not in known]
            if len(missing) != 1:
                continue
            value = _solved(equation, missing[0], known)
            if value is not None:
                known[missing[0]] = value
                changed = True
    completed = dict(point)
    completed.update({s.name: v for s, v in known.items() if s in system.index_of and s.name not in point})
    return completed


def _solved(equation: sympy.Expr, unknown: sympy.Symbol, known: dict) -> float | None:
    coefficient = partial(equation, unknown)
    if coefficient == 0 or unknown in free_symbols(coefficient):
        return None
    try:
        rest = float(equation.xreplace({unknown: sympy.Integer(0)}).xreplace(known))
        slope = float(coefficient.xreplace(known))
    except (TypeError, ValueError, OverflowError):   # symbolic, complex, or beyond any float
        return None
    if slope == 0.0 or not math.isfinite(rest / slope):
        return None
    return -rest / slope
