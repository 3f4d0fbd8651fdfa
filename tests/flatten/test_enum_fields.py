"""Enum members with fields (`| Ramp(rate::Real = 1)`): a parameter is given a member with field
values, `Ramp(rate = 3)`, and the case of a `switch` on it that names the member binds the fields,
in order, to names local to the case: `case Ramp(r)`. Mistakes are located errors."""
from __future__ import annotations


from tests.flatten.conftest import residuals, solved_single_unknown

MODES = """
enum Start =
  | Rest
  | At(x0::Real)
  | Ramp(rate::Real = 1, offset::Real = 0)

component Block
  parameter x_given::Real = 7
  parameter mode::Start = Start.At(x0 = x_given)
  variable x::Real
relations
  switch mode
    case Rest
      x = 0
    case At(value)
      x = value
    case Ramp(r, o)
      x = r * 10 + o
  end
end
"""


def test_the_default_binds_a_field_written_with_a_parameter_of_the_block(sources):
    assert solved_single_unknown(sources.flatten(MODES, "Block")) == 7


def test_a_modifier_gives_fields_by_name_by_position_or_leaves_their_defaults(sources):
    for given, expected in (("Start.At(x0 = 2.5)", 2.5), ("Start.Ramp(3, 0.5)", 30.5),
                            ("Start.Ramp(offset = 4)", 14), ("Start.Ramp", 10),
                            ("Start.Rest()", 0)):
        flat = sources.flatten(MODES + f"""
component Top
  block = Block(mode = {given})
end
""", "Top")
        assert solved_single_unknown(flat) == expected, given


def test_a_member_passed_on_through_a_parameter_keeps_its_fields(sources):
    flat = sources.flatten(MODES + """
component Outer
  parameter start::Start = Start.At(x0 = -1)
  block = Block(mode = start)
end
""", "Outer")
    assert residuals(flat) == {"block.x + 1"}


def test_an_unknown_field_is_a_located_error(sources):
    err = sources.error(MODES + """
component Top
  block = Block(mode = Start.At(x1 = 2))
end
""", "Top", marker="x1 = 2")
    assert "enum member `Start.At` has no field `x1`" in err.message


def test_a_missing_field_that_a_case_binds_is_a_located_error(sources):
    err = sources.error(MODES + """
component Top
  block = Block(mode = Start.At())
end
""", "Top", marker="Start.At()")
    assert "`block.mode` is `Start.At` without its field `x0`" in err.message
    assert err.hint == "write `Start.At(x0 = ...)`"


def test_too_many_values_and_too_many_bound_names_are_located_errors(sources):
    err = sources.error(MODES + """
component Top
  block = Block(mode = Start.At(1, 2))
end
""", "Top", marker="Start.At(1, 2)")
    assert "has 1 field(s) (x0) but is given 2 values" in err.message
    err = sources.error(MODES.replace("case At(value)", "case At(value, extra)"), "Block",
                        marker="case At(value, extra)")
    assert "binds 2 name(s) but `Start.At` has 1 field(s)" in err.message
