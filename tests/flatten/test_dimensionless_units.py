"""`units = 1` (a number) is Dyad's way to write a dimensionless unit; Julia's `identity` returns
its argument."""
from __future__ import annotations

import sympy


def test_units_written_as_the_number_one_are_dimensionless(sources):
    flat = sources.flatten("""
component Model
  variable s::Real(units = 1)
  variable v::Real(final units = "V")
relations
  s = 2
  v = 3 * s
end
""", "Model")
    units = {v.name: v.units for v in flat.variables}
    assert units["s"] == "1"
    assert units["v"] == "V"


def test_units_given_as_another_number_are_an_error(sources):
    err = sources.error("""
component Model
  variable s::Real(units = 2)
relations
  s = 2
end
""", "Model", marker="units = 2")
    assert "`units` must be a string" in err.message


def test_identity_returns_its_argument(sources):
    flat = sources.flatten("""
component Model
  variable x::Real
  variable v::Real[2]
relations
  x = identity(x > 1 ? 2 : 3) + 1
  v = identity([x, 2 * x])
end
""", "Model")
    residuals = [e.residual for e in flat.equations]
    assert len(residuals) == 3
    x = sympy.Symbol("x")
    assert residuals[0].subs(x, 3) == 0          # x = 2 + 1 when x > 1
    assert residuals[2].subs({x: 3, sympy.Symbol("v[2]"): 6}) == 0
