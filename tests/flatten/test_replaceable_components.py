"""Replaceable components: a keyword-less typed declaration `sensor::Sensor = Thermometer()` in a
component is a subcomponent of the constructor's type, which a modifier giving another constructor
replaces (`Rig(sensor = Doubler(k = 3))`); the replacement must extend the declared type."""
from __future__ import annotations

import sympy

LIB = """
connector In = input Real
connector Out = output Real

partial component Sensor
  u = In()
  y = Out()
end

component Thermometer
  extends Sensor
  parameter k::Real = 1
relations
  y = k * u
end

component Doubler
  extends Sensor
  parameter k::Real = 2
relations
  y = 2 * k * u
end

component Unrelated
  u = In()
  y = Out()
relations
  y = u
end

component Rig
  sensor::Sensor = Thermometer(k = 5)
  variable x::Real
relations
  x = 3
  sensor.u = x
end
"""


def _sensor_equation(flat) -> sympy.Expr:
    (equation,) = [e.residual for e in flat.equations if sympy.Symbol("sensor.y") in e.residual.free_symbols]
    return equation


def _gain(flat) -> float:
    values = {p.name: p.value for p in flat.parameters}
    equation = _sensor_equation(flat).subs({sympy.Symbol(n): v for n, v in values.items() if v is not None})
    return float(sympy.solve(equation.subs(sympy.Symbol("sensor.u"), 1), sympy.Symbol("sensor.y"))[0])


def test_the_declared_constructor_is_the_default(sources):
    flat = sources.flatten(LIB, "Rig")
    assert _gain(flat) == 5


def test_a_modifier_replaces_the_component_type(sources):
    flat = sources.flatten(LIB + """
component Top
  rig = Rig(sensor = Doubler(k = 3))
end
""", "Top")
    values = {p.name: p.value for p in flat.parameters}
    assert values["rig.sensor.k"] == 3
    residual = next(e.residual for e in flat.equations
                    if sympy.Symbol("rig.sensor.y") in e.residual.free_symbols)
    assert sympy.simplify(residual - (sympy.Symbol("rig.sensor.y")
                                      - 2 * sympy.Symbol("rig.sensor.k") * sympy.Symbol("rig.sensor.u"))) == 0


def test_a_modifier_without_constructor_modifies_the_default(sources):
    flat = sources.flatten(LIB + """
component Top
  rig = Rig(sensor(k = 7))
end
""", "Top")
    values = {p.name: p.value for p in flat.parameters}
    assert values["rig.sensor.k"] == 7


def test_a_replacement_must_extend_the_declared_type(sources):
    err = sources.error(LIB + """
component Top
  rig = Rig(sensor = Unrelated())
end
""", "Top", marker="rig = Rig(sensor = Unrelated())")
    assert "`Unrelated` cannot replace `sensor`" in err.message.replace("Model.", "")


def test_a_typed_value_declaration_asks_for_parameter_or_variable(sources):
    err = sources.error("""
component Model
  k::Real = 2
  variable x::Real
relations
  x = 1
end
""", "Model", marker="k::Real = 2")
    assert "declares neither a parameter nor a variable" in err.message


def test_a_replaceable_without_a_component_is_a_located_error(sources):
    err = sources.error(LIB + """
component Empty
  probe::Sensor
end
""", "Empty", marker="probe::Sensor")
    assert "replaceable component `probe` has no component" in err.message
