"""Vector and matrix equations expand to scalars; selections stay continuous; der uses the
chain rule."""
from __future__ import annotations

import sympy

from tests.flatten.conftest import residuals

S = sympy.Symbol


def equations_of(flat) -> list[sympy.Expr]:
    return [e.residual for e in flat.equations]


def test_vector_arithmetic_expands_elementwise(sources):
    flat = sources.flatten("""
component Model
  parameter r::Real[2] = [1, 2]
  parameter c::Real = 3
  variable a::Real[2]
  variable b::Real[2]
  variable d::Real[2]
relations
  a = r + [c, c]
  b = c * a - r / 2
  d = a .* b
end
""", "Model")
    eqs = equations_of(flat)
    assert len(eqs) == 6
    assert sympy.simplify(eqs[0] - (S("a[1]") - S("r[1]") - S("c"))) == 0
    assert sympy.simplify(eqs[3] - (S("b[2]") - S("c") * S("a[2]") + S("r[2]") / 2)) == 0
    assert sympy.simplify(eqs[5] - (S("d[2]") - S("a[2]") * S("b[2]"))) == 0


def test_matrix_literal_times_vector_rotation(sources):
    flat = sources.flatten("""
component Model
  parameter r::Real[2] = [1, 0]
  variable phi::Real
  variable r0::Real[2]
relations
  phi = 0.5
  r0 = [cos(phi) -sin(phi); sin(phi) cos(phi)] * r
end
""", "Model")
    eqs = equations_of(flat)
    phi, r1, r2 = S("phi"), S("r[1]"), S("r[2]")
    assert sympy.simplify(eqs[1] - (S("r0[1]") - (sympy.cos(phi) * r1 - sympy.sin(phi) * r2))) == 0
    assert sympy.simplify(eqs[2] - (S("r0[2]") - (sympy.sin(phi) * r1 + sympy.cos(phi) * r2))) == 0


def test_norm_dot_sum_fill_zeros_and_slicing(sources):
    flat = sources.flatten("""
component Model
  variable v::Real[3]
  variable n::Real
  variable d::Real
  variable s::Real
  variable last::Real
  variable head::Real[2]
  variable z::Real[2]
  variable f::Real[2]
relations
  v = [1, 2, 3]
  n = norm(v[1:2])
  d = dot(v, [1, 1, 1])
  s = sum(v[2:end])
  last = v[end]
  head = v[1:2]
  z = zeros(2)
  f = fill(n, 2)
end
""", "Model")
    got = residuals(flat)
    assert "n - sqrt(v[1]**2 + v[2]**2)" in got
    assert "d - v[1] - v[2] - v[3]" in got
    assert "s - v[2] - v[3]" in got
    assert "last - v[3]" in got
    assert {"head[1] - v[1]", "head[2] - v[2]", "z[1]", "z[2]", "f[1] - n", "f[2] - n"} <= got


def test_selections_stay_continuous_piecewise(sources):
    flat = sources.flatten("""
component Model
  variable x::Real
  variable y::Real
  variable z::Real
relations
  x = sin(time)
  y = ifelse(x > 0, x, 0)
  z = if x > 0.5 then 1 elseif x < -0.5 then -1 else 0
end
""", "Model")
    eqs = equations_of(flat)
    assert eqs[1].has(sympy.Piecewise) and eqs[2].has(sympy.Piecewise)
    x = S("x")
    y_of = sympy.solve(eqs[1], S("y"))[0]
    assert y_of.subs(x, 2) == 2 and y_of.subs(x, -2) == 0
    z_of = sympy.solve(eqs[2], S("z"))[0]
    assert [float(z_of.subs(x, v)) for v in (1, 0, -1)] == [1, 0, -1]


def test_der_of_a_composite_expression_uses_the_chain_rule(sources):
    flat = sources.flatten("""
component Model
  parameter L::Real = 2
  variable x::Real
  variable y::Real
relations
  der(L * x ^ 2 + time) = y
  x = sin(y)
end
""", "Model")
    eq = equations_of(flat)[0]
    expected = 2 * S("L") * S("x") * S("der(x)") + 1 - S("y")
    assert sympy.simplify(eq - expected) == 0
    assert flat.variable("x").kind == "state_candidate"
    assert flat.variable("y").kind == "algebraic"


def test_vector_der_and_indexing_with_loop_variables(sources):
    flat = sources.flatten("""
component Model
  variable r::Real[2]
  variable v::Real[2]
relations
  v = der(r)
  for i in 1:2
    der(v[i]) = -r[i]
  end
end
""", "Model")
    assert residuals(flat) == {"-der(r[1]) + v[1]", "-der(r[2]) + v[2]", "der(v[1]) + r[1]",
                               "der(v[2]) + r[2]"}
    assert sorted(flat.derivatives) == ["der(r[1])", "der(r[2])", "der(v[1])", "der(v[2])"]


def test_power_binds_tighter_than_unary_minus(sources):
    flat = sources.flatten("""
component Model
  variable x::Real
relations
  x = -2 ^ 2
end
""", "Model")
    assert residuals(flat) == {"x + 4"}
