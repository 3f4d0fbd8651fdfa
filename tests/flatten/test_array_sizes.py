"""Array sizes are known at compile time even when the elements are unknowns: `size(u, 1)` of a
variable can size a parameter or select a branch; `size` of a scalar is 1 along any dimension (as
in Julia); `prod` multiplies the elements of an array."""
from __future__ import annotations

import sympy


def test_size_of_a_variable_sizes_a_parameter_and_selects_a_branch(sources):
    flat = sources.flatten("""
component Model
  variable u::Real[3]
  variable y::Real
  parameter gains::Real[size(u, 1)] = fill(2, size(u, 1))
relations
  u = [1, 2, 3]
  if size(u, 1) > 2
    y = sum(gains .* u)
  else
    y = 0
  end
end
""", "Model")
    values = {p.name: p.value for p in flat.parameters}
    assert [values[f"gains[{i}]"] for i in (1, 2, 3)] == [2, 2, 2]
    y_equation = next(e.residual for e in flat.equations if sympy.Symbol("y") in e.residual.free_symbols)
    assert sympy.Symbol("u[3]") in y_equation.free_symbols       # the `if` branch was taken


def test_size_of_a_scalar_is_one(sources):
    flat = sources.flatten("""
component Model
  variable u::Real
  variable y::Real
relations
  u = 2
  y = size(u, 1) + size(u, 2)
end
""", "Model")
    y_equation = next(e.residual for e in flat.equations if sympy.Symbol("y") in e.residual.free_symbols)
    assert y_equation.subs(sympy.Symbol("y"), 2) == 0


def test_prod_of_an_array_and_of_a_scalar(sources):
    flat = sources.flatten("""
component Model
  variable u::Real[3]
  variable p::Real
  variable q::Real
relations
  u = [2, 3, 4]
  p = prod(u)
  q = prod(p)
end
""", "Model")
    residuals = {str(e.residual) for e in flat.equations}
    assert "p - u[1]*u[2]*u[3]" in residuals
    assert "-p + q" in residuals


def test_size_dimension_must_be_positive(sources):
    err = sources.error("""
component Model
  variable u::Real[2]
  variable y::Real
relations
  u = [1, 2]
  y = size(u, 0)
end
""", "Model", marker="size(u, 0)")
    assert "dimension 0 out of range" in err.message
