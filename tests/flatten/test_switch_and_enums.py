"""Enum values and `switch` on a structural enum parameter: `Gear.High` (or `Gear.High()`) is the
member's 1-based position; `switch` keeps the relations of the case its subject selects (`else`
when none), cases written bare (the subject's enum) or qualified; mistakes are located errors."""
from __future__ import annotations

import math

import pytest
import sympy

from compiler.api import simulate

ENUM = """
enum Gear = Low | Middle | High

component Box
  structural parameter g::Gear = Gear.High
  variable x::Real
relations
  switch g
  case Low
    x = 1
  case Gear.Middle
    x = 2
  else
    x = 3
  end
end
"""


def _x_value(flat) -> float:
    (equation,) = [e.residual for e in flat.equations]
    (x,) = equation.free_symbols
    return float(sympy.solve(equation, x)[0])


def test_the_default_member_selects_the_else_branch(sources):
    assert _x_value(sources.flatten(ENUM, "Box")) == 3


def test_a_modifier_selects_a_bare_and_a_qualified_case(sources):
    for member, expected in (("Gear.Low", 1), ("Gear.Middle()", 2)):
        flat = sources.flatten(ENUM + f"""
component Top
  box = Box(g = {member})
end
""", "Top")
        assert _x_value(flat) == expected


def test_enum_values_are_positions_and_compare_in_conditions(sources):
    flat = sources.flatten(ENUM + """
component Uses
  structural parameter g::Gear = Gear.Middle
  variable y::Real
relations
  if g == Gear.Middle
    y = Gear.High
  else
    y = 0
  end
end
""", "Uses")
    (equation,) = [e.residual for e in flat.equations]
    assert equation == sympy.Symbol("y") - 3


def test_an_unknown_member_is_a_located_error(sources):
    err = sources.error(ENUM.replace("= Gear.High", "= Gear.Top"), "Box", marker="Gear.Top")
    assert "enum `Gear` has no member `Top`" in err.message


def test_a_bare_case_on_a_non_enum_subject_is_a_located_error(sources):
    err = sources.error("""
component Plain
  structural parameter n::Integer = 1
  variable x::Real
relations
  switch n
  case One
    x = 1
  end
end
""", "Plain", marker="case One")
    assert "cannot tell which enum `One` belongs to" in err.message


def test_a_member_without_fields_takes_no_arguments(sources):
    err = sources.error(ENUM.replace("= Gear.High", "= Gear.High(ratio = 2)"), "Box",
                        marker="Gear.High(ratio")
    assert "enum member `Gear.High` has no fields" in err.message


CLOSED_CASES = """
enum Law = Decay | Growth | Hold

component Rate
  structural parameter law::Law = Law.Decay
  parameter k::Real = 2
  variable x::Real
relations
  initial x = 1
  switch law
    case Decay
      der(x) = -k * x
    end
    case Growth
      der(x) = k
    end
    else
      der(x) = 0
    end
  end
end
"""


@pytest.mark.parametrize("law, expected", [("Law.Decay", math.exp(-1.0)), ("Law.Growth", 2.0),
                                           ("Law.Hold", 1.0)])
def test_cases_closed_by_end_select_the_law_that_simulates(sources, law, expected):
    """Dyad's form, each case closed by `end`: x(0.5) of x' = -2x, x' = 2, x' = 0 from x(0) = 1."""
    path = sources.write("Rate.dyad", CLOSED_CASES + f"""
component Top
  rate = Rate(law = {law})
end
""")
    result = simulate(f"{path}:Top", stop=0.5, rtol=1e-9, atol=1e-11)
    assert result["rate.x"][-1] == pytest.approx(expected, rel=1e-6)
