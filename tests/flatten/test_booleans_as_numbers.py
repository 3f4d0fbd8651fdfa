"""Booleans are numbers in Dyad (true = 1, false = 0): a condition assigned to a Boolean variable
or used in arithmetic becomes a 1/0 selection; a Boolean variable used as a condition is true
above one half (so its changes are located like any crossing); `not(c)` is `!c`."""
from __future__ import annotations

import pytest
import sympy

from compiler.api import simulate

S = sympy.Symbol


def _value_at(flat_residual, **values) -> float:
    return float(flat_residual.subs({S(k): v for k, v in values.items()}))


def test_condition_assigned_to_a_boolean_is_one_or_zero(sources):
    flat = sources.flatten("""
component Model
  parameter level::Real = 2
  variable x::Real
  variable high::Boolean
relations
  x = 3
  high = x >= level
end
""", "Model")
    residual = next(e.residual for e in flat.equations if S("high") in e.residual.free_symbols)
    # residual = high - selection: zero exactly when high is the 1/0 value of the comparison
    assert _value_at(residual, high=1, x=3, level=2) == 0
    assert _value_at(residual, high=0, x=1, level=2) == 0
    assert _value_at(residual, high=1, x=1, level=2) == 1


def test_boolean_in_arithmetic_counts_one(sources):
    flat = sources.flatten("""
component Model
  variable n::Real
  variable x::Real
relations
  x = 5
  n = (x > 1) + (x > 2) + (x > 10)
end
""", "Model")
    residual = next(e.residual for e in flat.equations if S("n") in e.residual.free_symbols)
    assert _value_at(residual, n=2, x=5) == 0


def test_not_function_and_bang_on_a_boolean_variable(sources):
    flat = sources.flatten("""
component Model
  variable on::Boolean
  variable off1::Boolean
  variable off2::Boolean
relations
  on = 1
  off1 = !on
  off2 = not(on)
end
""", "Model")
    for name in ("off1", "off2"):
        residual = next(e.residual for e in flat.equations if S(name) in e.residual.free_symbols)
        assert _value_at(residual, **{name: 0, "on": 1}) == 0
        assert _value_at(residual, **{name: 1, "on": 0}) == 0


def test_not_on_a_structural_parameter_selects_a_declaration(sources):
    flat = sources.flatten("""
component Model
  structural parameter wanted::Boolean = false
  parameter a::Real = 1 if wanted
  parameter b::Real = 2 if not(wanted)
  variable x::Real
relations
  x = b
end
""", "Model")
    names = {p.name for p in flat.parameters}
    assert "b" in names and "a" not in names


def test_not_takes_one_argument(sources):
    err = sources.error("""
component Model
  variable x::Real
relations
  x = not(1, 2)
end
""", "Model", marker="not(1, 2)")
    assert "`not` takes one argument" in err.message


def test_a_boolean_signal_switches_an_integral_at_its_crossing(sources, tmp_path):
    # y is 1 after t = 0.25 (a Boolean from a comparison), so x(1) = 0.75 exactly
    path = sources.write("Switched.dyad", """
component Switched
  variable y::Boolean
  variable x::Real
relations
  initial x = 0
  y = time > 0.25
  der(x) = y
end
""")
    result = simulate(f"{path}:Switched", stop=1.0, rtol=1e-8, atol=1e-10)
    assert result["x"][-1] == pytest.approx(0.75, abs=1e-6)
