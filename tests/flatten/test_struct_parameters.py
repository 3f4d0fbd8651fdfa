"""Parameters of a `struct` type are records of parameters (`mat.mu_i`): values come, highest
precedence first, from modifiers where the component is used, the constructor given as value,
the declared type's and aliases' modifiers, then the fields' defaults."""
from __future__ import annotations

import pytest

from compiler.api import simulate

SOURCE = """
struct Material
  mu_i::Real = 1
  loss::Real = 0.5
  label::String = "generic"
end

type Steel = Material(mu_i = 200, label = "steel")
type HotSteel = Steel(loss = 2)

component Core
  parameter mat::Material
  variable x::Real
relations
  initial x = 0
  der(x) = mat.mu_i + mat.loss
end
"""


def _values(flat) -> dict:
    return {p.name: p.value for p in flat.parameters}


@pytest.mark.parametrize("use, mu_i, loss", [
    ("core = Core()", 1, 0.5),                                   # the fields' defaults
    ("core = Core(mat = Steel())", 200, 0.5),                    # an alias as constructor
    ("core = Core(mat = HotSteel(mu_i = 3))", 3, 2),             # alias of an alias, overridden
    ("core = Core(mat = Material(loss = 4))", 1, 4),             # the struct itself
    ("core = Core(mat(loss = 7))", 1, 7),                        # a field modifier
])
def test_field_values_follow_the_precedence(sources, use, mu_i, loss):
    flat = sources.flatten(SOURCE + f"""
component Top
  {use}
end
""", "Top")
    values = _values(flat)
    assert values["core.mat.mu_i"] == mu_i
    assert values["core.mat.loss"] == loss


def test_a_declared_constructor_and_a_typed_declaration(sources):
    flat = sources.flatten(SOURCE + """
component Typed
  parameter a::Steel
  parameter b::Material = Steel(loss = 1)
  variable y::Real
relations
  y = a.mu_i + b.loss
end
""", "Typed")
    values = _values(flat)
    assert (values["a.mu_i"], values["a.loss"]) == (200, 0.5)
    assert (values["b.mu_i"], values["b.loss"]) == (200, 1)


def test_struct_fields_are_tunable_parameters_at_run_time(sources):
    path = sources.write("Run.dyad", SOURCE + """
component Top
  core = Core(mat = Steel())
end
""")
    result = simulate(f"{path}:Top", stop=1.0, params={"core.mat.loss": 1.0})
    assert result["core.x"][-1] == pytest.approx(201.0, rel=1e-6)


def test_a_constructor_of_another_struct_is_a_located_error(sources):
    err = sources.error(SOURCE + """
struct Other
  mu_i::Real = 1
end

component Top
  core = Core(mat = Other())
end
""", "Top", marker="core = Core(mat = Other())")
    assert "`Other` is not a `Material`" in err.message.replace("Model.", "")


def test_an_unknown_field_is_a_located_error(sources):
    err = sources.error(SOURCE + """
component Top
  core = Core(mat = Steel(mu = 3))
end
""", "Top", marker="core = Core(mat = Steel(mu = 3))")
    assert "has no parameter, variable or component `mu`" in err.message
