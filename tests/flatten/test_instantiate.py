"""Instantiation: extends, modifiers, final, parameter dependencies, structural parameters,
arrays, component arrays, conditional declarations, initial values and guesses."""
from __future__ import annotations

import sympy

from compiler.model.flat import ALGEBRAIC, INPUT, OUTPUT, STATE_CANDIDATE
from tests.flatten.conftest import parameter_value, residuals

BASES = """
partial component Base
  parameter k::Real = 1
  parameter offset::Real = 10
  variable x::Real
end

component Middle
  extends Base(k = 2)
  parameter gain::Real = k * 3
end
"""


def test_extends_chain_with_modifier_precedence(sources):
    flat = sources.flatten(BASES + """
component Model
  extends Middle(offset = 5)
  a = Middle(k = 7)
  variable y::Real
relations
  x = k + offset
  y = a.x
  a.x = a.gain
end
""", "Model")
    assert parameter_value(flat, "k") == 2             # Middle's extends modifier
    assert parameter_value(flat, "offset") == 5        # Model's extends modifier
    assert parameter_value(flat, "gain") == 6          # default in terms of another parameter
    assert parameter_value(flat, "a.k") == 7           # outer modifier beats Middle's
    assert parameter_value(flat, "a.gain") == 21
    gain = next(p for p in flat.parameters if p.name == "a.gain")
    assert gain.default == 3 * sympy.Symbol("a.k")     # the binding stays symbolic
    assert {"-k - offset + x", "-a.x + y", "-a.gain + a.x"} == residuals(flat)


def test_several_extends(sources):
    flat = sources.flatten("""
partial component HasA
  variable a::Real
end
partial component HasB
  parameter pb::Real = 4
  variable b::Real
end
component Model
  extends HasA()
  extends HasB(pb = 5)
relations
  a = 1
  b = pb
end
""", "Model")
    assert [v.name for v in flat.variables] == ["a", "b"]
    assert parameter_value(flat, "pb") == 5


def test_nested_modifiers_reach_a_subcomponent_variable(sources):
    flat = sources.flatten("""
component Joint
  variable phi::Real
  variable w::Real
relations
  w = der(phi)
  der(w) = -phi
end
component Holder
  j = Joint(phi(guess = 0.1))
end
component Model
  h = Holder(j(phi(initial = 0.3, state_priority = 5)), j.w(initial = 0))
end
""", "Model")
    phi = flat.variable("h.j.phi")
    assert phi.start == 0.3 and phi.guess == 0.1 and phi.state_priority == 5
    assert phi.kind == STATE_CANDIDATE
    assert flat.variable("h.j.w").start == 0
    assert {str(e.residual) for e in flat.initial_equations} == {"h.j.phi - 0.3", "h.j.w"}
    assert flat.guesses["h.j.phi"] == 0.1


def test_initial_forms_and_guesses(sources):
    flat = sources.flatten("""
component Model
  parameter x0::Real = 2
  variable x::Real = initial x0
  variable y::Real(guess = 7)
  variable z::Real
relations
  der(x) = -x
  y = 2 * x
  der(z) = y
  initial z = 3 * x0
  guess y = 8
end
""", "Model")
    assert flat.variable("x").start == 2
    assert flat.variable("z").start == 6
    assert flat.guesses["y"] == 8                     # the relation comes after the type modifier
    assert {str(e.residual) for e in flat.initial_equations} == {"x - x0", "-3*x0 + z"}
    assert flat.derivatives == {"der(x)": "x", "der(z)": "z"}


def test_binding_equation_and_modifier_binding(sources):
    flat = sources.flatten("""
component Inner
  variable u::Real
  variable v::Real = 2 * u
end
component Model
  inner = Inner(u = 4)
end
""", "Model")
    assert residuals(flat) == {"inner.u - 4", "-2*inner.u + inner.v"}
    kinds = {e.kind for e in flat.equations}
    assert kinds == {"binding"}


def test_structural_parameters_set_sizes_and_branches(sources):
    flat = sources.flatten("""
component Model
  structural parameter n::Integer = 3
  parameter l::Real[n] = [1, 2, 3]
  variable x::Real[n]
  variable A::Real[2, n]
  variable s::Real
relations
  for i in 1:n
    x[i] = l[i] * i
    A[1, i] = i
    A[2, i] = n
  end
  if n > 2
    s = 1
  else
    s = 2
  end
end
""", "Model")
    names = [v.name for v in flat.variables]
    assert names == ["x[1]", "x[2]", "x[3]", "A[1,1]", "A[1,2]", "A[1,3]", "A[2,1]", "A[2,2]",
                     "A[2,3]", "s"]
    assert "-3*l[3] + x[3]" in residuals(flat)
    assert "A[2,2] - 3" in residuals(flat)            # structural parameter substituted
    assert "s - 1" in residuals(flat)
    n = next(p for p in flat.parameters if p.name == "n")
    assert not n.tunable and n.variability == "structural"
    assert [p.name for p in flat.parameters if p.name.startswith("l")] == ["l[1]", "l[2]", "l[3]"]


def test_parameter_used_as_a_size_becomes_fixed(sources):
    flat = sources.flatten("""
component Model
  parameter m::Integer = 2
  parameter other::Real = 1
  variable x::Real[m]
relations
  x = fill(other, m)
end
""", "Model")
    tunable = {p.name: p.tunable for p in flat.parameters}
    assert tunable == {"m": False, "other": True}


def test_component_arrays_and_conditional_declarations(sources):
    flat = sources.flatten("""
component Link
  parameter L::Real = 1
  variable y::Real
relations
  y = L
end
component Model
  structural parameter n::Integer = 3
  parameter l::Real[n] = [0.5, 0.25, 0.125]
  parameter use_extra::Boolean = false
  links = [Link(L = l[i]) for i in 1:n]
  extra = Link() if use_extra
  variable total::Real
relations
  total = sum([links[i].y for i in 1:n])
end
""", "Model")
    assert [v.name for v in flat.variables] == ["total", "links[1].y", "links[2].y", "links[3].y"]
    assert parameter_value(flat, "links[2].L") == 0.25
    link_default = next(p for p in flat.parameters if p.name == "links[2].L").default
    assert link_default == sympy.Symbol("l[2]")
    assert "-links[1].y - links[2].y - links[3].y + total" in residuals(flat)


def test_conditional_declaration_enabled(sources):
    flat = sources.flatten("""
component Part
  variable q::Real
relations
  q = 1
end
component Model
  structural parameter with_part::Boolean = true
  part = Part() if with_part
end
""", "Model")
    assert [v.name for v in flat.variables] == ["part.q"]


def test_booleans_are_numbers(sources):
    flat = sources.flatten("""
component Model
  parameter on::Boolean = true
  parameter off::Boolean = !on
  variable x::Real
relations
  x = ifelse(on, 1, 2) + off
end
""", "Model")
    assert parameter_value(flat, "on") == 1 and parameter_value(flat, "off") == 0


def test_variable_kinds_for_signals(sources):
    flat = sources.flatten("""
component Model
  u = RealInput()
  y = RealOutput()
  variable s::Real
  variable a::Real
relations
  der(s) = u
  y = s
  a = 2 * y
end
""", "Model")
    kinds = {v.name: v.kind for v in flat.variables}
    assert kinds == {"u": INPUT, "y": OUTPUT, "s": STATE_CANDIDATE, "a": ALGEBRAIC}


def test_visual_only_components_stay_out_of_the_numerics(sources):
    flat = sources.flatten("""
partial component Looks
  parameter render::Boolean = true
  parameter color::Real[4] = [0.5, 0.5, 0.5, 1.0]
end
component Shape
  extends Looks()
  parameter size::Real = 1
end
component Model
  extends Looks(color = [1, 0, 0, 1])
  parameter scale::Real = 2
  shape = Shape(size = scale, render = render)
  variable x::Real
relations
  x = scale
metadata {"Dyad": {"tests": {"case1": {"stop": 1}}}}
end
""", "Model")
    assert [p.name for p in flat.parameters] == ["scale"]
    assert flat.visual["shape"] == {"type": "Shape", "parameters": {
        "render": True, "color": [0.5, 0.5, 0.5, 1.0], "size": 2.0}}
    assert flat.visual[""]["parameters"]["color"] == [1.0, 0.0, 0.0, 1.0]
    assert flat.metadata["Dyad"] == {"tests": {"case1": {"stop": 1}}}
