"""What the rest of the published syntax (issue 27, item 3) means once flattened: relative
`using`, `time` as a declared name, `path` declarations, `switch` everywhere, filtered and nested
comprehensions, enums in every position. Models written for these tests."""
from __future__ import annotations

import pytest

from compiler.errors import DyadError
from compiler.model.flatten import flatten_model
from tests.syntax.test_rest_of_published_syntax import SWITCH_VALUES as BOX_WITH_SWITCH_VALUES


@pytest.fixture
def rig_spring(sources):
    """`Rig.Parts.Spring`, which the `using` tests import from other files."""
    sources.write("Rig/Parts/Spring.dyad", """
        component Spring
          parameter k::Real = 3
          variable f::Real
        relations
          f = k
        end
    """)


def test_relative_usings_name_definitions_from_the_files_package(sources, rig_spring):
    sources.write("Rig/Tools/Damper.dyad", """
        using ..Parts: Spring
        component Damper
          s = Spring(k = 5)
        end
    """)
    sources.write("Rig/Bench.dyad", """
        using .Tools
        using .Parts: Spring
        component Bench
          d = Damper()
          s = Spring()
        end
    """)
    flat = flatten_model("Rig.Bench", [str(sources.root)])
    assert sorted(v.name for v in flat.variables) == ["d.s.f", "s.f"]
    assert {p.name: p.value for p in flat.parameters if p.name.endswith(".k")} == {"d.s.k": 5, "s.k": 3}


CLOCK = """
    component Clock
      variable time::Real
      variable elapsed::Real
    relations
      initial time = 0
      der(time) = 2
      elapsed = time
    end
    component Rig
      c = Clock()
      variable y::Real
    relations
      y = time
    end
"""


def test_a_renamed_using_names_the_definition_by_its_new_name_only(sources, rig_spring):
    """Julia's `using P: a as b`: `b` is P's `a` in this file (also as the head of a dotted
    name); the old name `a` is not brought in."""
    sources.write("Bench.dyad", """
        using Rig: Parts as P
        using Rig.Parts: Spring as Coil
        component Bench
          a = Coil(k = 4)
          b = P.Spring()
        end
        component Old
          c = Spring()
        end
    """)
    flat = flatten_model("Bench", [str(sources.root)])
    assert {p.name: p.value for p in flat.parameters if p.name.endswith(".k")} == {"a.k": 4, "b.k": 3}
    with pytest.raises(DyadError) as caught:
        flatten_model("Old", [str(sources.root)])
    assert "unknown component type `Spring`" in caught.value.message
    assert (caught.value.span.line, caught.value.span.column) == (8, 3)


def test_a_declared_time_shadows_the_independent_variable_inside_its_component(sources):
    path = sources.write("Clock.dyad", CLOCK)
    from compiler.api import simulate
    result = simulate(f"{path}:Rig", stop=1.0, points=3, codegen="vm")
    assert result["c.elapsed"][-1] == pytest.approx(2.0, rel=1e-6)     # its own clock, twice as fast
    assert result["y"][-1] == pytest.approx(1.0, rel=1e-9)             # the independent variable


def test_time_declared_by_the_simulated_model_itself_is_a_located_error(sources):
    path = sources.write("Clock.dyad", CLOCK)
    with pytest.raises(DyadError) as caught:
        flatten_model(f"{path}:Clock")
    err = caught.value
    assert (err.span.line, err.span.column) == (2, 3)
    assert err.message == ("`time` cannot be declared by the simulated model itself: its flat name "
                           "would be the independent variable's")
    assert err.hint == "simulate a component that contains this one (`c = Clock()`), where it is `c.time`, or rename it (`t_local`)"


def test_filtered_and_nested_comprehensions_are_vectors_in_julias_order(sources):
    flat = sources.flatten("""
        component C
          parameter n::Integer = 3
          parameter odd::Real[:] = [i^2 for i in 1:5 if i % 2 == 1]
          parameter pairs::Real[:] = [10 * i + j for i in 1:n for j in i:n if j > i]
          parameter total::Real = sum(i for i in 1:n if i > 1)
          parameter grid::Real[2, 3] = [i + j for i in 1:2, j in 1:3]
          variable x::Real
        relations
          x = sum(odd) + sum(pairs) + total + grid[2, 3]
        end
    """)
    values = {p.name: p.value for p in flat.parameters}
    assert [values[f"odd[{k}]"] for k in (1, 2, 3)] == [1, 9, 25]
    assert [values[f"pairs[{k}]"] for k in (1, 2, 3)] == [12, 13, 23]
    assert "pairs[4]" not in values and values["total"] == 5 and values["grid[2,3]"] == 5


def test_a_filter_on_a_run_time_value_is_a_located_error(sources):
    err = sources.error("""
        component C
          variable x::Real
          variable y::Real[2] = [x * i for i in 1:3 if x > i]
        relations
          x = 1
        end
    """, marker="if x > i")
    assert err.message.startswith("the `if` filter of a comprehension must be known when the model is compiled")
    assert (err.span.column, err.notes[0].message) == (48, "a parameter expression cannot depend on variable `x`")


def test_an_enum_of_a_package_file_types_parameters_with_defaults_and_selects_cases(sources):
    sources.write("Drive/Interfaces/Choices.dyad", """
        "How the gear is chosen"
        enum GearChoice =
          | Low
          | High
    """)
    sources.write("Drive/Box.dyad", """
        using .Interfaces: GearChoice
        component Box
          structural parameter gear::GearChoice = GearChoice.Low()
          parameter ratio::Real = if gear == Drive.Interfaces.GearChoice.High then 4 else 2
          variable y::Real
        relations
          switch gear
            case GearChoice.Low()
              y = ratio
            end
            case Interfaces.GearChoice.High()
              y = 10 * ratio
            end
          end
        end
    """)
    sources.write("Drive/Rig.dyad", """
        component Rig
          low = Box()
          high = Box(gear = Interfaces.GearChoice.High())
        end
    """)
    flat = flatten_model("Drive.Rig", [str(sources.root)])
    values = {p.name: p.value for p in flat.parameters}
    assert (values["low.gear"], values["high.gear"]) == (1, 2)
    equations = {str(e.residual) for e in flat.equations}
    assert equations == {"-low.ratio + low.y", "-10*high.ratio + high.y"}


def test_nested_switches_keep_the_relations_both_subjects_select(sources):
    text = """
        enum Gear = Low | High
        enum Road = Dry | Wet
        component Box
          structural parameter gear::Gear = Gear.Low()
          structural parameter road::Road = Road.Dry()
          variable y::Real
        relations
          switch gear
            case Gear.Low()
              y = 1
            end
            case Gear.High()
              switch road
                case Dry
                  y = 2
                end
                case Road.Wet()
                  y = 3
                end
              end
            end
          end
        end
        component Rig
          a = Box()
          b = Box(gear = Gear.High())
          c = Box(gear = Gear.High(), road = Road.Wet())
        end
    """
    flat = sources.flatten(text, "Rig")
    assert {str(e.residual) for e in flat.equations} == {"a.y - 1", "b.y - 2", "c.y - 3"}


def test_path_declarations_with_defaults_add_no_unknowns(sources):
    flat = sources.flatten("""
        type Medium = Native
        connector Port
          potential p::Real
          flow m::Real
          path medium::Medium = Water()
        end
        component Pipe
          path medium::Medium = Oil()
          a = Port(medium = medium)
          b = Port()
        relations
          continuity(a.medium, b.medium, medium)
          a.m + b.m = 0
          a.p - b.p = a.m
        end
        component Rig
          pipe = Pipe()
        relations
          pipe.a.p = 1
          pipe.b.p = 0
        end
    """, "Rig")
    assert sorted(v.name for v in flat.variables) == ["pipe.a.m", "pipe.a.p", "pipe.b.m", "pipe.b.p"]


# the Box of the syntax tests (parsed and printed there), here instantiated twice
SWITCH_VALUES = BOX_WITH_SWITCH_VALUES + """
component Rig
  low = Box(gear = Gear.Low())
  high = Box()
end
"""


def test_a_switch_value_is_the_value_of_the_case_its_subject_selects(sources):
    flat = sources.flatten(SWITCH_VALUES, "Rig")
    assert {p.name: p.value for p in flat.parameters if p.name.endswith(".k")} == {"low.k": 1.5, "high.k": 2.5}
    assert {str(e.residual) for e in flat.equations} == {"-low.k + low.y", "-3*high.k + high.y"}


def test_a_switch_value_without_the_selected_case_or_else_is_a_located_error(sources):
    err = sources.error(SWITCH_VALUES.replace("Box(gear = Gear.Low())", "Box(gear = Gear.Top())")
                        .replace("    else\n      3 * k\n    end\n", ""), "Rig", marker="y = switch gear")
    assert err.message == "no case of this `switch` names the value of its subject, and it has no `else`"
    assert err.span.column == 7


def test_an_if_expression_inside_a_case_of_a_switch_value_is_the_cases_value(sources):
    flat = sources.flatten("""
        enum Gear = Low | High
        component C
          structural parameter gear::Gear = Gear.High()
          parameter wet::Boolean = false
          variable y::Real
        relations
          y = switch gear
            case Low
              if wet then 1 else 2
            end
            else
              if wet then 3 else 4
            end
          end
        end
    """)
    (equation,) = flat.equations
    assert str(equation.residual) == "y - Piecewise((3, wet > 1/2), (4, True))"


def test_documented_enums_compare_and_a_switch_reads_a_subcomponents_enum(sources):
    """The enum forms of Dyad's documented libraries: a docstring before `enum X = | A | B`, a
    member named `None`, `!=` between enum values in an if-expression, and a switch value whose
    subject is a structural enum parameter of a subcomponent (`switch b.states`)."""
    text = """
        "Which orientation states a body keeps."
        enum Orientation = | None | Euler | Quaternion
        "The frame nearer the root."
        enum Rooted
          | FrameA
          | FrameB
        end
        component Body
          structural parameter states::Orientation = Orientation.None()
          structural parameter rooted::Rooted = Rooted.FrameA()
          variable y::Real
        relations
          switch states
            case None
              y = 0
            end
            case Euler, Quaternion
              y = if rooted != Rooted.FrameA() then 2 else 1
            end
          end
        end
        component Rig
          plain = Body()
          b = Body(states = Orientation.Euler(), rooted = Rooted.FrameB())
          variable z::Real = switch b.states
            case None
              0
            end
            else
              b.y
            end
          end
        end
    """
    flat = sources.flatten(text, "Rig")
    assert {str(e.residual) for e in flat.equations} == {"plain.y", "b.y - 2", "-b.y + z"}
