"""Julia's generator arguments, `sum(w[i] * x[i] for i in 1:n)` (issue 27 item 3): the call of the
comprehension `[... for ...]`, so sums, products and reductions over an index read as written."""
from __future__ import annotations

import math

import pytest

from compiler.api import simulate

WEIGHTED = """
component Weighted
  structural parameter n::Integer = 3
  parameter w::Real[n] = [1.0, 2.0, 3.0]
  variable x::Real[n]
  variable total::Real
relations
  for i in 1:n
    initial x[i] = 1
    der(x[i]) = -i * x[i]
  end
  total = sum(w[i] * x[i] for i in 1:n)
end
"""


def test_a_weighted_sum_over_states_matches_its_closed_form(sources):
    path = sources.write("Weighted.dyad", WEIGHTED)
    result = simulate(f"{path}:Weighted", stop=0.5, rtol=1e-9, atol=1e-11)
    # x_i(t) = exp(-i t), so total(t) = sum_i i * exp(-i t)
    expected = sum(i * math.exp(-i * 0.5) for i in (1, 2, 3))
    assert result["total"][-1] == pytest.approx(expected, rel=1e-6)


def test_a_product_over_two_iterators_is_the_product_of_all_terms(sources):
    path = sources.write("Ramp.dyad", """
component Ramp
  parameter a::Real[2] = [2.0, 3.0]
  variable z::Real
relations
  initial z = 0
  der(z) = prod(a[i] + j for i in 1:2, j in 0:1)
end
""")
    result = simulate(f"{path}:Ramp", stop=2.0, rtol=1e-9, atol=1e-11)
    # (2 + 0)(3 + 0)(2 + 1)(3 + 1) = 72, so z(2) = 144
    assert result["z"][-1] == pytest.approx(144.0, rel=1e-8)


def test_a_generator_in_a_scalar_function_is_a_located_size_error(sources):
    err = sources.error("""
component Wrong
  parameter a::Real[3] = [1.0, 2.0, 3.0]
  variable y::Real
relations
  y = sin(a[i] for i in 1:3)
end
""", "Wrong", marker="y = sin(")
    assert "array size mismatch" in err.message
