"""Hand-built ReducedSystems: the runtime's inputs, written the way the structural passes emit them."""
from __future__ import annotations


import sympy

from compiler.errors import Span
from compiler.model.flat import TIME, Origin
from compiler.structure.reduced import Assignment, InitialProblem, ParameterInfo, ReducedSystem

S = sympy.Symbol


def _origin(path: str, line: int) -> Origin:
    return Origin(path, Span("model.dyad", line, 3, line, 20))


def robertson() -> ReducedSystem:
    """Robertson's stiff chemical kinetics in DAE form (y3 from the conservation law)."""
    y1, y2, y3 = S("y1"), S("y2"), S("y3")
    k1, k2, k3 = S("k1"), S("k2"), S("k3")
    alg = [y1 + y2 + y3 - 1]
    return ReducedSystem(
        name="Robertson", states=["y1", "y2"],
        ode=[-k1 * y1 + k2 * y2 * y3, k1 * y1 - k2 * y2 * y3 - k3 * y2**2],
        algebraics=["y3"], alg=alg, assignments=[], observables=[],
        parameters=[ParameterInfo("k1", 0.04), ParameterInfo("k2", 1e4), ParameterInfo("k3", 3e7)],
        initial=InitialProblem(residuals=alg + [y1 - 1, y2],
                               origins=[_origin("", 4), _origin("", 7), _origin("", 8)],
                               guesses={"y3": 0.5}),
        output_names=["y1", "y2", "y3"])


def pendulum_angle(theta0: float = 1.0) -> ReducedSystem:
    """A pendulum in minimal coordinates: der(theta) = omega, der(omega) = -g/L sin(theta)."""
    th, om, g, length, th0 = S("theta"), S("omega"), S("g"), S("L"), S("theta0")
    return ReducedSystem(
        name="PendulumAngle", states=["theta", "omega"],
        ode=[om, -g / length * sympy.sin(th)], algebraics=[], alg=[], assignments=[],
        observables=[Assignment("x", length * sympy.sin(th)), Assignment("y", -length * sympy.cos(th))],
        parameters=[ParameterInfo("g", 9.81), ParameterInfo("L", 1.0), ParameterInfo("theta0", theta0)],
        initial=InitialProblem(residuals=[th - th0, om], origins=[_origin("", 3), _origin("", 4)]),
        output_names=["theta", "omega", "x", "y"])


def pendulum_cartesian(theta0: float = 1.0, redundant: bool = True,
                       y_start: float | None = None) -> ReducedSystem:
    """Semi-explicit index-1 pendulum: positions and velocities as states, the rod tension `lam`
    (per unit length and mass) algebraic, from the acceleration-level constraint.

    With `redundant`, the initial problem also demands x^2 + y^2 = L^2 (consistent with the
    given x, y). `y_start` replaces y's start value: inconsistent with that constraint.
    """
    x, y, vx, vy, lam = S("x"), S("y"), S("vx"), S("vy"), S("lam")
    g, length, th0 = S("g"), S("L"), S("theta0")
    ax, ay = S("ax"), S("ay")
    alg = [x * ax + y * ay + vx**2 + vy**2]
    y0 = -length * sympy.cos(th0) if y_start is None else sympy.Float(y_start)
    residuals = alg + [x - length * sympy.sin(th0), y - y0, vx, vy]
    origins = [_origin("", 10), _origin("", 20), _origin("", 21), _origin("", 22), _origin("", 23)]
    if redundant:
        residuals.append(x**2 + y**2 - length**2)
        origins.append(_origin("rod", 30))
    return ReducedSystem(
        name="PendulumCartesian", states=["x", "y", "vx", "vy"], ode=[vx, vy, ax, ay],
        algebraics=["lam"], alg=alg,
        assignments=[Assignment("ax", -lam * x), Assignment("ay", -lam * y - g)],
        observables=[Assignment("theta", sympy.atan2(x, -y)),
                     Assignment("rod_error", sympy.sqrt(x**2 + y**2) - length)],
        parameters=[ParameterInfo("g", 9.81), ParameterInfo("L", 1.0), ParameterInfo("theta0", theta0)],
        initial=InitialProblem(residuals=residuals, origins=origins,
                               guesses={"x": 0.5, "y": -0.5, "lam": 1.0}),
        output_names=["x", "y", "vx", "vy", "lam", "theta", "rod_error"])


def rc_circuit() -> ReducedSystem:
    """A voltage step V into R in series with C: v' = i/C, 0 = V - R i - v. v(t) = V (1 - e^{-t/RC})."""
    v, i, big_v, r, c = S("C.v"), S("R.i"), S("V"), S("R"), S("C")
    alg = [big_v - S("R.v") - v]
    return ReducedSystem(
        name="RC", states=["C.v"], ode=[i / c], algebraics=["R.i"], alg=alg,
        assignments=[Assignment("R.v", r * i)],
        observables=[Assignment("R.power", S("R.v") * i)],
        parameters=[ParameterInfo("V", 10.0), ParameterInfo("R", 100.0), ParameterInfo("C", 1e-3)],
        initial=InitialProblem(residuals=alg + [v], origins=[_origin("R", 5), _origin("C", 6)]),
        output_names=["C.v", "R.i", "R.v", "R.power", "der(C.v)"])


def valve_tank() -> ReducedSystem:
    """Assignments, observables and dependent parameters: two orifices into a tank,
    `Kv_b = Kv * area_b / area_a` (a dependent default), `tau = 1 / Kv_b` (bound to it in turn)."""
    h, q_in, q_out = S("h"), S("q_in"), S("q_out")
    kv, kv_b, area_a, area_b, tau, supply = (S("Kv"), S("Kv_b"), S("area_a"), S("area_b"),
                                             S("tau"), S("supply"))
    return ReducedSystem(
        name="ValveTank", states=["h"], ode=[(q_in - q_out) / area_a], algebraics=[], alg=[],
        assignments=[Assignment("q_in", kv * (supply - h)), Assignment("q_out", kv_b * h)],
        observables=[Assignment("net", q_in - q_out), Assignment("time_scale", tau)],
        parameters=[ParameterInfo("area_a", 2.0), ParameterInfo("area_b", 0.5),
                    ParameterInfo("Kv", 4.0), ParameterInfo("Kv_b", 1.0, kv * area_b / area_a),
                    ParameterInfo("tau", 1.0, 1 / kv_b), ParameterInfo("supply", 3.0),
                    ParameterInfo("rho", 1000.0, tunable=False)],
        initial=InitialProblem(residuals=[h - 0.0], origins=[_origin("tank", 2)]),
        output_names=["h", "q_in", "q_out", "net", "Kv_b", "time_scale"])


def vanishing_root() -> ReducedSystem:
    """0 = z^2 + t - 1 has real solutions only until t = 1: the solver must fail there."""
    x, z = S("x"), S("z")
    return ReducedSystem(
        name="VanishingRoot", states=["x"], ode=[z], algebraics=["z"], alg=[z**2 + TIME - 1],
        assignments=[], observables=[], parameters=[],
        initial=InitialProblem(residuals=[z**2 + TIME - 1, x], origins=[None, None],
                               guesses={"z": 0.9}),
        output_names=["x", "z"])


def mass_chain(n: int = 20, heavy: bool = False) -> ReducedSystem:
    """A mid-size model: n masses on nonlinear springs with dampers, forces as algebraic unknowns
    (each spring force defined implicitly by its own residual), driven at the first mass.
    `heavy` uses the excavator scene's kind of smooth laws (saturation, regularised roots, trig),
    whose evaluation cost makes compiled C pay off."""
    states, ode, algebraics, alg, residuals = [], [], [], [], []
    params = [ParameterInfo("m", 1.0), ParameterInfo("k", 100.0), ParameterInfo("k3", 50.0),
              ParameterInfo("d", 0.5), ParameterInfo("A", 0.1), ParameterInfo("w", 3.0)]
    m, k, k3, d, amp, w = (S(q.name) for q in params)
    drive = amp * sympy.sin(w * TIME)
    for j in range(1, n + 1):
        states += [f"s{j}", f"v{j}"]
        algebraics.append(f"f{j}")
    for j in range(1, n + 1):
        left = drive if j == 1 else S(f"s{j - 1}")
        left_v = amp * w * sympy.cos(w * TIME) if j == 1 else S(f"v{j - 1}")
        stretch = S(f"s{j}") - left
        slip = S(f"v{j}") - left_v
        if heavy:
            law = (k * stretch / (1 + (stretch / 0.2) ** 4) ** sympy.Rational(1, 4)
                   + k3 * sympy.sin(stretch) * sympy.cos(2 * stretch)
                   + d * slip / (slip**2 + 0.01) ** sympy.Rational(1, 4)
                   + d * sympy.tanh(10 * slip) * sympy.exp(-stretch**2))
        else:
            law = k * stretch + k3 * stretch**3 + d * slip
        alg.append(S(f"f{j}") - law)
        pull_right = S(f"f{j + 1}") if j < n else 0
        ode += [S(f"v{j}"), (pull_right - S(f"f{j}")) / m]
    residuals = list(alg) + [S(s) for s in states]
    return ReducedSystem(
        name=f"MassChain{n}{'Heavy' if heavy else ''}", states=states, ode=ode, algebraics=algebraics, alg=alg,
        assignments=[], observables=[], parameters=params,
        initial=InitialProblem(residuals=residuals, origins=[None] * len(residuals)),
        output_names=states + algebraics)


ALL = {"robertson": robertson, "pendulum_angle": pendulum_angle,
       "pendulum_cartesian": pendulum_cartesian, "rc_circuit": rc_circuit,
       "valve_tank": valve_tank, "vanishing_root": vanishing_root, "mass_chain": mass_chain}



def draining() -> ReducedSystem:
    """der(x) = -1 from x = 1, with x declared `min = 0`: the bound is crossed at t = 1."""
    x = S("x")
    return ReducedSystem(
        name="Draining", states=["x"], ode=[sympy.Integer(-1)], algebraics=[], alg=[],
        assignments=[], observables=[], parameters=[],
        initial=InitialProblem([x - 1], [None]), output_names=["x"],
        metadata={"bounds": {"x": {"min": 0.0}}})
