"""Hand-built FlatSystems for testing the structure stage without the front end."""
from __future__ import annotations

import sympy

from compiler.model.flat import ALGEBRAIC, STATE_CANDIDATE, Equation, FlatSystem, Origin, Parameter, Variable


def build(name, variables, parameters, equations, initial=(), derivatives=None):
    """variables: list of (name, kind, start, priority); equations: list of sympy residuals."""
    vs = [Variable(n, kind, start=start, state_priority=prio) for n, kind, start, prio in variables]
    ps = [Parameter(n, float(v), sympy.Float(v)) for n, v in parameters]
    eqs = [Equation(r, Origin(name)) for r in equations]
    init = [Equation(r, Origin(name)) for r in initial]
    ders = derivatives or {f"der({v.name})": v.name for v in vs if v.kind == STATE_CANDIDATE}
    return FlatSystem(name, vs, ps, eqs, init, ders)


def S(name):
    return sympy.Symbol(name)


def D(name):
    return sympy.Symbol(f"der({name})")


def capacitor_mirror_named(u0=0.0):
    """capacitor_mirror with the second equation's derivatives named by an auxiliary variable,
    a = y1' - y2' (the dependency on e1 hides behind a)."""
    from compiler.model.flat import TIME
    y1, y2, a, C, R0, R1, R2, Ub = (S(n) for n in "y1 y2 a C R0 R1 R2 Ub".split())
    eqs = [a - (D("y1") - D("y2")),
           C * (D("y1") - D("y2")) + (y1 - sympy.sin(TIME)) / R0,
           -C * a + y2 * (1 / R1 + 1 / R2) - Ub / R2]
    return build("MirrorNamed", [("y1", STATE_CANDIDATE, None, 0), ("y2", STATE_CANDIDATE, None, 0),
                                 ("a", ALGEBRAIC, None, 0)],
                 [("C", 1.0), ("R0", 1.0), ("R1", 2.0), ("R2", 2.0), ("Ub", 1.0)], eqs,
                 initial=[y1 - y2 - u0], derivatives={"der(y1)": "y1", "der(y2)": "y2"})


def cartesian_pendulum(x0=1.0, y0=0.0, L=1.0, g=9.81, redundant=False):
    x, y, u, v, T = (S(n) for n in "x y u v T".split())
    Ls, gs = S("L"), S("g")
    eqs = [D("x") - u, D("y") - v, D("u") + T * x, D("v") + T * y + gs, x**2 + y**2 - Ls**2]
    initial = [x - x0, u] + ([y - y0] if redundant else [])
    variables = [("x", STATE_CANDIDATE, x0, 0), ("y", STATE_CANDIDATE, y0, 0),
                 ("u", STATE_CANDIDATE, 0.0, 0), ("v", STATE_CANDIDATE, 0.0, 0), ("T", ALGEBRAIC, None, 0)]
    return build("Pendulum", variables, [("L", L), ("g", g)], eqs, initial)


def capacitor_mirror(u0=0.0):
    """Derivatives only as C*(der(y1) - der(y2)) and its mirror: one true state (y1 - y2).

    e1:  C (y1' - y2') + (y1 - sin t)/R0 = 0
    e2: -C (y1' - y2') + y2 (1/R1 + 1/R2) - Ub/R2 = 0
    """
    from compiler.model.flat import TIME
    y1, y2, C, R0, R1, R2, Ub = (S(n) for n in "y1 y2 C R0 R1 R2 Ub".split())
    eqs = [C * (D("y1") - D("y2")) + (y1 - sympy.sin(TIME)) / R0,
           -C * (D("y1") - D("y2")) + y2 * (1 / R1 + 1 / R2) - Ub / R2]
    return build("Mirror", [("y1", STATE_CANDIDATE, None, 0), ("y2", STATE_CANDIDATE, None, 0)],
                 [("C", 1.0), ("R0", 1.0), ("R1", 2.0), ("R2", 2.0), ("Ub", 1.0)], eqs,
                 initial=[y1 - y2 - u0])
