"""Arrays of signal connectors written as a comprehension, `u = [RealInput() for i in 1:n]`
(issue 27, item 3; compiler/model/signal_arrays.py): one array variable whose elements are
connected one by one (`connect(a.y, m.u[2])`) or given by equations; modifiers shared by every
element; a modifier that depends on the iterator is a located error."""
from __future__ import annotations

import pytest

from compiler.api import simulate

MUX = """
component Mux
  parameter n::Integer = 3
  u = [RealInput() for i in 1:n]
  y = RealOutput()
relations
  y = sum(k * u[k] for k in 1:n)
end

component Source
  parameter value::Real = 1
  y = RealOutput()
relations
  y = value
end
"""


def test_elements_connected_one_by_one_each_carry_their_source(sources):
    path = sources.write("Model.dyad", MUX + """
    component Rig
      m = Mux(n = 3)
      a = Source(value = 2)
      b = Source(value = 5)
    relations
      connect(a.y, m.u[1])
      connect(b.y, m.u[3])
      m.u[2] = time
    end
    """)
    result = simulate(f"{path}:Rig", stop=2.0, points=3)
    assert result["m.y"][-1] == pytest.approx(1 * 2 + 2 * 2.0 + 3 * 5, abs=1e-12)
    assert result["m.u[3]"][-1] == 5


def test_the_array_has_one_element_per_iteration(sources):
    flat = sources.flatten(MUX, "Mux")
    inputs = sorted(v.name for v in flat.variables if v.name.startswith("u["))
    assert inputs == ["u[1]", "u[2]", "u[3]"]


def test_an_element_left_unconnected_is_an_unconnected_input(sources):
    error = sources.error(MUX + """
    component Rig
      m = Mux(n = 2)
      a = Source()
    relations
      connect(a.y, m.u[1])
    end
    """, "Rig", marker="m = Mux(n = 2)")
    assert "input `m.u[2]` is not connected and no equation gives it a value" in error.message


def test_a_modifier_that_depends_on_the_iterator_is_located(sources):
    error = sources.error("""
    component Bad
      u = [RealInput(guess = i) for i in 1:2]
    end
    """, "Bad", marker="u = [RealInput(guess = i)")
    assert error.message == ("a modifier of the signal connector array `u` depends on its "
                             "iterator `i`: every element of such an array shares its modifiers")


def test_elements_of_a_sized_input_connect_the_same_way(sources):
    path = sources.write("Model.dyad", MUX + """
    component Pair
      input u::Real[2]
      output y::Real
    relations
      y = u[1] - u[2]
    end

    component Rig
      p = Pair()
      a = Source(value = 7)
      b = Source(value = 3)
    relations
      connect(a.y, p.u[1])
      connect(b.y, p.u[2])
    end
    """)
    result = simulate(f"{path}:Rig", stop=1.0, points=2)
    assert result["p.y"][-1] == 4
