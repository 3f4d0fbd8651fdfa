"""The rest of the published syntax (issue 27, item 3): `using` in Julia's forms, `time` as a
declared name, `path` declarations, `switch` everywhere, filtered and nested comprehensions,
`enum` in every position. What each form parses into and the located errors around them;
examples written for these tests from Dyad's documentation, not copied."""
import pytest

from compiler.errors import DyadError
from compiler.syntax import ast
from compiler.syntax.format import format_file
from compiler.syntax.parser import parse_source


def parse(text: str) -> ast.File:
    result = parse_source(text, "t.dyad")
    assert parse_source(format_file(result), "t.dyad<fmt>") == result     # fmt round-trips
    return result


def error(text: str) -> DyadError:
    with pytest.raises(DyadError) as caught:
        parse_source(text, "t.dyad")
    assert caught.value.span is not None and caught.value.span.file == "t.dyad"
    return caught.value


# ------------------------------------------------------------------------------------- using

def test_using_forms_absolute_relative_and_several_on_a_line():
    usings = parse("using Gears\nusing Gears.Spur, .Local\nusing ..Sibling.Deep: Shaft, Hub\n"
                   "component C\nend\n").usings
    assert [(u.level, u.package, u.names) for u in usings] == [
        (0, "Gears", ()), (0, "Gears.Spur", ()), (1, "Local", ()),
        (2, "Sibling.Deep", ("Shaft", "Hub"))]
    assert [u.written for u in usings] == ["Gears", "Gears.Spur", ".Local", "..Sibling.Deep"]


@pytest.mark.parametrize("written, within, absolute", [
    ("using .Sub", "Pkg.Inner", "Pkg.Inner.Sub"),
    ("using ..Sibling", "Pkg.Inner", "Pkg.Sibling"),
    ("using ..Other", "Pkg", "Other"),
    ("using Plain", "Pkg.Inner", "Plain"),
])
def test_a_relative_using_counts_its_dots_from_the_files_package(written, within, absolute):
    (using,) = parse(written + "\n").usings
    assert using.absolute_package(within) == absolute


def test_a_relative_using_above_the_top_level_is_a_located_error():
    (using,) = parse("\n  using ...Far: x\n").usings
    with pytest.raises(DyadError) as caught:
        using.absolute_package("Pkg")
    err = caught.value
    assert (err.span.line, err.span.column) == (2, 3)
    assert "above the top-level packages" in err.message and err.hint == "name the package absolutely: `using Far`"


def test_using_renames_listed_names_as_julia_does():
    (using,) = parse("using ..Gears.Spur: Wheel as W, Hub, Axle as A\n").usings
    assert (using.names, using.local_names) == (("Wheel", "Hub", "Axle"), ("W", "Hub", "A"))
    assert [using.imported(n) for n in ("W", "Hub", "A", "Wheel", "Axle")] == ["Wheel", "Hub", "Axle", None, None]
    assert format_file(parse_source("using P: a as b, c\n", "t.dyad")) == "using P: a as b, c\n"
    assert parse("using P: a as a\n").usings == parse("using P: a\n").usings     # renamed to itself


def test_a_word_other_than_as_between_two_using_names_is_a_located_error():
    err = error("using P: a to b\n")
    assert (err.span.line, err.span.column, err.message) == (
        1, 12, "expected `as` or `,` after `a` in this `using`, found `to`")
    assert err.hint == "rename with `a as b`, or list names with commas"


def test_as_stays_an_ordinary_name_outside_using():
    (definition,) = parse("component C\n  parameter as::Real = 1\nend\n").definitions
    assert definition.declarations[0].name == "as"


# ------------------------------------------------------------------ comprehensions: filters, nesting

def parameter_value(text: str) -> ast.Expr:
    (definition,) = parse(f"component T\n  parameter v::Real[:] = {text}\nend\n").definitions
    return definition.declarations[0].default


def test_a_filtered_comprehension_keeps_its_condition():
    comp = parameter_value("[i^2 for i in 1:5 if i > 2]")
    assert isinstance(comp, ast.Comprehension) and comp.is_vector and comp.more == ()
    assert [it.variable for it in comp.iterators] == ["i"]
    assert comp.condition == ast.BinaryOp(">", ast.Ref((ast.RefPart("i"),)), ast.Number(2))


def test_nested_fors_each_with_its_own_filter_and_a_generator_argument():
    comp = parameter_value("[i * j for i in 1:3 if i > 1 for j in 1:i, k in 1:2 if j != k]")
    assert [[it.variable for it in c.iterators] for c in comp.clauses] == [["i"], ["j", "k"]]
    assert [c.condition is not None for c in comp.clauses] == [True, True]
    call = parameter_value("sum(i for i in 1:4 if i % 2 == 0)")
    (generator,) = call.args
    assert generator.generator and generator.condition is not None


def test_a_comprehension_spread_over_lines_is_not_a_matrix():
    comp = parameter_value("[i\n    for i in 1:3\n    if i > 1]")
    assert isinstance(comp, ast.Comprehension) and comp.condition is not None


def test_an_array_of_components_with_a_filter_is_a_located_error():
    err = error("component T\n  r = [R() for i in 1:3 if i > 1]\nend\n")
    assert (err.span.line, err.span.column) == (2, 12)
    assert err.message.startswith("an array of components takes one `for` clause without a filter")


# -------------------------------------------------------------------------------- switch, enums

GEARS = """enum Gear = Low | High
enum Road = Dry | Wet
component Box
  structural parameter gear::Gear = Gear.Low()
  structural parameter road::Road = Road.Dry()
  variable y::Real
relations
  switch gear
    case Gear.Low(), Gear.High
      switch road
        case Dry
          y = 1
        end
        case Road.Wet()
          y = 2
        end
      end
    end
  end
end
"""


def test_cases_name_members_bare_qualified_or_as_values_and_switches_nest():
    box = parse(GEARS).definitions[2]
    (outer,) = box.relations
    (case,) = outer.cases
    assert case.names == ("Gear.Low()", "Gear.High") and case.members == ("Gear.Low", "Gear.High")
    (inner,) = case.body
    assert [c.names for c in inner.cases] == [("Dry",), ("Road.Wet()",)]
    assert inner.closed_cases and outer.closed_cases


def test_a_member_listed_twice_with_and_without_parentheses_is_one_case_too_many():
    err = error(GEARS.replace("case Gear.Low(), Gear.High", "case Gear.Low(), Gear.Low"))
    assert (err.span.line, err.message) == (9, "case `Gear.Low` appears twice in this `switch`")


def test_an_enum_inside_a_component_is_a_located_error_with_where_to_put_it():
    err = error("component C\n  enum Mode = Fast | Slow\nend\n")
    assert (err.span.line, err.span.column) == (2, 3)
    assert err.message == ("an `enum` is a definition of its own, declared at the top level of a "
                           "file, not inside component `C`")
    assert err.hint.startswith("move `enum Mode ...` above `component C`")


def test_type_equals_enum_is_a_located_error():
    err = error("type Mode = enum Low | High\n")
    assert (err.span.column, err.hint) == (13, "write `enum X = A | B`; an alias of it is `type Y = X`")


# -------------------------------------------------------------------------------------- path

def test_path_declarations_in_connectors_and_components_with_and_without_defaults():
    port, pipe = parse("""connector Port
  potential p::Real
  flow m::Real
  "the fluid of the whole network" path medium::Medium = Water(rho = 1000) {"Dyad": {}}
end
component Pipe
  path medium::Medium
  path fluid::Medium = Oil() if wet
  a = Port(medium = medium)
end
""").definitions
    medium = port.fields[2]
    assert (medium.kind, medium.doc, medium.value.function) == ("path", "the fluid of the whole network", "Water")
    assert port.fields[0].value is None
    plain, conditional = pipe.declarations[:2]
    assert (plain.kind, plain.value, conditional.kind, conditional.value.function) == ("path", None, "path", "Oil")
    assert conditional.condition is not None


def test_a_default_on_a_connector_field_other_than_path_is_a_located_error():
    err = error("connector Port\n  potential p::Real = 1\nend\n")
    assert (err.span.line, err.span.column) == (2, 23)
    assert err.message == "only a `path` field of a connector has a default value, not a `potential` field"


SWITCH_VALUES = """enum Gear = Low | High | Top
component Box
  structural parameter gear::Gear = Gear.High()
  parameter k::Real = switch gear
    case Low
      1.5
    end
    case Gear.High(), Top
      2.5
    end
  end
  variable y::Real
relations
  y = switch gear
    case Low
      k
    end
    else
      3 * k
    end
  end
end
"""


def test_a_switch_gives_a_value_in_a_declaration_and_in_an_equation():
    box = parse(SWITCH_VALUES).definitions[1]
    value = box.declarations[1].default
    assert isinstance(value, ast.SwitchValue) and value.otherwise == ()
    assert [c.names for c in value.cases] == [("Low",), ("Gear.High()", "Top")]
    assert value.cases[1].body == (ast.Number(2.5),)
    (equation,) = box.relations
    assert isinstance(equation.rhs, ast.SwitchValue) and len(equation.rhs.otherwise) == 1


def test_a_switch_value_inside_a_larger_expression_is_a_located_error():
    err = error(SWITCH_VALUES.replace("y = switch gear", "y = 2 * switch gear"))
    assert (err.span.line, err.span.column) == (14, 11)
    assert err.message == "a `switch` value stands alone right after `=`, not inside a larger expression"
    assert err.hint == "give it a name of its own: `variable s::Real = switch ...`, then use `2 * s`"


def test_fmt_prints_a_switch_value_on_one_line_that_reads_back_the_same():
    printed = format_file(parse(SWITCH_VALUES))
    assert "  parameter k::Real = switch gear; case Low; 1.5; end; case Gear.High(), Top; 2.5; end; end\n" in printed
    assert parse_source(printed, "again.dyad") == parse(SWITCH_VALUES)


def test_switch_still_names_a_component_after_an_equals_sign():
    (component,) = parse("component T\n  switch = Toggle()\nrelations\n  y = switch.on\nend\n").definitions
    assert component.relations[0].rhs == ast.Ref((ast.RefPart("switch"), ast.RefPart("on")))
