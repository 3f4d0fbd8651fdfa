"""Connection semantics on classic cases: potentials equal, flows sum to zero with the
inside/outside rule, unconnected flows zero, signals driven by their source."""
from __future__ import annotations

import sympy

from compiler.model.flatten import check_balance

ELECTRICAL = """
connector Pin
  potential v::Real
  flow i::Real
end

partial component TwoPin
  p = Pin()
  n = Pin()
  variable v::Real
  variable i::Real
relations
  v = p.v - n.v
  0 = p.i + n.i
  i = p.i
end

component Resistor
  extends TwoPin()
  parameter R::Real = 1
relations
  v = R * i
end

component VoltageSource
  extends TwoPin()
  parameter V::Real = 1
relations
  v = V
end

component Ground
  p = Pin()
relations
  p.v = 0
end
"""


def solve_numeric(flat, extra_unknowns=()) -> dict[str, float]:
    """Solve the (linear, algebraic) flat system with the parameter values substituted."""
    values = {sympy.Symbol(p.name): p.value for p in flat.parameters}
    unknowns = [sympy.Symbol(v.name) for v in flat.variables] + list(extra_unknowns)
    eqs = [e.residual.xreplace(values) for e in flat.equations]
    solution = sympy.solve(eqs, unknowns, dict=True)
    assert len(solution) == 1
    return {str(k): float(v) for k, v in solution[0].items()}


def test_resistor_network(sources):
    flat = sources.flatten(ELECTRICAL + """
component Circuit
  source = VoltageSource(V = 10)
  r1 = Resistor(R = 100)
  r2 = Resistor(R = 200)
  r3 = Resistor(R = 300)
  ground = Ground()
relations
  connect(source.p, r1.p)
  connect(r1.n, r2.p, r3.p)
  connect(r2.n, r3.n, source.n, ground.p)
end
""", "Circuit")
    check_balance(flat)
    solution = solve_numeric(flat)
    total = 10 / (100 + 200 * 300 / 500)
    assert abs(solution["r1.i"] - total) < 1e-12
    assert abs(solution["r2.i"] - total * 300 / 500) < 1e-12
    assert abs(solution["source.i"] + total) < 1e-12       # current enters p of the source
    assert abs(solution["ground.p.i"]) < 1e-12
    kinds = sorted({e.kind for e in flat.equations})
    assert kinds == ["connect", "equation", "flow"]


def test_hierarchical_connector_enters_with_opposite_sign(sources):
    flat = sources.flatten(ELECTRICAL + """
component Divider
  p = Pin()
  n = Pin()
  upper = Resistor(R = 1)
  lower = Resistor(R = 3)
relations
  connect(p, upper.p)
  connect(upper.n, lower.p)
  connect(lower.n, n)
end

component Circuit
  source = VoltageSource(V = 8)
  divider = Divider()
  ground = Ground()
relations
  connect(source.p, divider.p)
  connect(divider.n, source.n, ground.p)
end
""", "Circuit")
    check_balance(flat)
    got = {str(e.residual) for e in flat.equations if e.kind == "flow"}
    assert "-divider.p.i + divider.upper.p.i" in got          # outside element counts -1
    solution = solve_numeric(flat)
    assert abs(solution["divider.upper.i"] - 2.0) < 1e-12
    assert abs(solution["divider.p.i"] - 2.0) < 1e-12


def test_unconnected_flows_are_zero(sources):
    flat = sources.flatten(ELECTRICAL + """
component Model
  r = Resistor()
  ground = Ground()
relations
  connect(r.n, ground.p)
end
""", "Model")
    unconnected = [str(e.residual) for e in flat.equations if e.kind == "unconnected_flow"]
    assert unconnected == ["r.p.i"]


ROTATIONAL = """
component Inertia
  flange_a = Spline()
  flange_b = Spline()
  parameter J::Real = 1
  variable phi::Angle
  variable w::AngularVelocity
relations
  phi = flange_a.phi
  phi = flange_b.phi
  w = der(phi)
  J * der(w) = flange_a.tau + flange_b.tau
end

component Spring
  flange_a = Spline()
  flange_b = Spline()
  parameter c::Real = 1
  variable tau::Torque
relations
  tau = c * (flange_b.phi - flange_a.phi)
  flange_b.tau = tau
  flange_a.tau = -tau
end

component Fixed
  flange = Spline()
relations
  flange.phi = 0
end
"""


def test_rotational_inertia_chain(sources):
    flat = sources.flatten(ROTATIONAL + """
component Chain
  fixed = Fixed()
  s1 = Spring(c = 2)
  j1 = Inertia(J = 3)
  s2 = Spring(c = 5)
  j2 = Inertia(J = 7)
relations
  connect(fixed.flange, s1.flange_a)
  connect(s1.flange_b, j1.flange_a)
  connect(j1.flange_b, s2.flange_a)
  connect(s2.flange_b, j2.flange_a)
end
""", "Chain")
    check_balance(flat)
    states = sorted(v.name for v in flat.variables if v.kind == "state_candidate")
    assert states == ["j1.phi", "j1.w", "j2.phi", "j2.w"]
    # Solve for everything but the states: the accelerations follow Newton's law (a flow is the
    # torque acting on the component, so a stretched spring pulls its flanges back).
    values = {sympy.Symbol(p.name): p.value for p in flat.parameters}
    state_symbols = {sympy.Symbol(s) for s in states}
    unknowns = [sympy.Symbol(v.name) for v in flat.variables if v.name not in states]
    unknowns += [sympy.Symbol(d) for d in flat.derivatives]
    solution = sympy.solve([e.residual.xreplace(values) for e in flat.equations], unknowns,
                           dict=True)[0]
    p1, p2 = sympy.Symbol("j1.phi"), sympy.Symbol("j2.phi")
    assert sympy.simplify(solution[sympy.Symbol("der(j1.w)")] - (-2 * p1 + 5 * (p2 - p1)) / 3) == 0
    assert sympy.simplify(solution[sympy.Symbol("der(j2.w)")] - (-5 * (p2 - p1)) / 7) == 0
    assert state_symbols


PLANAR = """
component World
  frame_b = Frame2D()
relations
  frame_b.x = 0
  frame_b.y = 0
  frame_b.phi = 0
end

component Revolute
  frame_a = Frame2D()
  frame_b = Frame2D()
  variable phi::Angle
  variable w::AngularVelocity
relations
  frame_a.x = frame_b.x
  frame_a.y = frame_b.y
  frame_b.phi = frame_a.phi + phi
  w = der(phi)
  frame_a.fx + frame_b.fx = 0
  frame_a.fy + frame_b.fy = 0
  frame_a.tau = 0
  frame_b.tau = 0
end

component FixedTranslation
  frame_a = Frame2D()
  frame_b = Frame2D()
  parameter r::Real[2] = [1, 0]
  variable r0::Real[2]
relations
  r0 = [cos(frame_a.phi) -sin(frame_a.phi); sin(frame_a.phi) cos(frame_a.phi)] * r
  frame_b.x = frame_a.x + r0[1]
  frame_b.y = frame_a.y + r0[2]
  frame_b.phi = frame_a.phi
  frame_a.fx + frame_b.fx = 0
  frame_a.fy + frame_b.fy = 0
  frame_a.tau + frame_b.tau + r0[1] * frame_b.fy - r0[2] * frame_b.fx = 0
end

component Body
  frame_a = Frame2D()
  parameter m::Real = 1
  parameter I::Real = 0.1
  variable r::Real[2]
  variable v::Real[2]
  variable a::Real[2]
  variable phi::Angle
  variable w::AngularVelocity
  variable alpha::AngularAcceleration
relations
  r = [frame_a.x, frame_a.y]
  v = der(r)
  a = der(v)
  phi = frame_a.phi
  w = der(phi)
  alpha = der(w)
  m * a = [frame_a.fx, frame_a.fy] + m * MultibodyComponents.PlanarMechanics.gravity_acceleration_2d()
  I * alpha = frame_a.tau
end
"""


def test_planar_pendulum_from_frame_components(sources):
    flat = sources.flatten(PLANAR + """
component Pendulum
  world = World()
  rev = Revolute(phi(initial = 0.3), w(initial = 0))
  rod = FixedTranslation(r = [0.5, 0])
  body = Body(m = 2, I = 0.05)
relations
  connect(world.frame_b, rev.frame_a)
  connect(rev.frame_b, rod.frame_a)
  connect(rod.frame_b, body.frame_a)
end
""", "Pendulum")
    check_balance(flat)            # balanced and structurally nonsingular (index 3 is fine)
    assert flat.variable("rev.phi").start == 0.3
    assert {"rev.phi", "body.r[1]", "body.v[2]", "body.phi", "body.w"} <= {
        v.name for v in flat.variables if v.kind == "state_candidate"}
    flows = [str(e.residual) for e in flat.equations if e.kind == "flow"]
    assert "rev.frame_b.fx + rod.frame_a.fx" in flows


def test_signals_drive_inputs(sources):
    flat = sources.flatten("""
component Gain
  u = RealInput()
  y = RealOutput()
  parameter k::Real = 2
relations
  y = k * u
end
component Source
  y = RealOutput()
relations
  y = sin(time)
end
component Model
  src = Source()
  g1 = Gain(k = 3)
  g2 = Gain()
  out = RealOutput()
relations
  connect(src.y, g1.u)
  connect(g1.y, g2.u, out)
end
""", "Model")
    check_balance(flat)
    connects = {str(e.residual) for e in flat.equations if e.kind == "connect"}
    assert connects == {"g1.u - src.y", "-g1.y + g2.u", "-g1.y + out"}
    assert flat.variable("out").kind == "output"


def test_an_input_given_by_an_equation_of_the_enclosing_component(sources):
    flat = sources.flatten("""
component Gain
  u = RealInput()
  y = RealOutput()
relations
  y = 2 * u
end
component Model
  g = Gain()
relations
  g.u = 1
end
""", "Model")
    check_balance(flat)
