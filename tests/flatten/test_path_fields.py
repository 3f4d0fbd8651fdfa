"""`path` connector fields carry a value of the whole connected path (e.g. a fluid medium defined
in Julia, type `Native`): they add no unknown and no equation, `continuity(...)` between them implies
no equation, and reading one in an expression is a located error. `stream` fields and `Native`
parameters are clear errors."""
from __future__ import annotations

import pytest

from compiler.api import simulate

PORT = """
type Fluid = Native

connector FluidPort
  potential p::Real
  flow q::Real
  path fluid::Fluid
end

component Source
  port = FluidPort()
  parameter p0::Real = 2
relations
  port.p = p0
end

component Orifice
  a = FluidPort()
  b = FluidPort()
  parameter k::Real = 4
relations
  continuity(a.fluid, b.fluid)
  a.q + b.q = 0
  a.q = k * (a.p - b.p)
end

component Tank
  port = FluidPort()
  variable level::Real
relations
  initial level = 0
  der(level) = port.q
  port.p = 0
end
"""


def test_path_fields_add_no_unknowns_and_the_circuit_simulates(sources):
    path = sources.write("Circuit.dyad", PORT + """
component Circuit
  src = Source()
  valve = Orifice()
  tank = Tank()
relations
  connect(src.port, valve.a)
  connect(valve.b, tank.port)
end
""")
    result = simulate(f"{path}:Circuit", stop=1.5, rtol=1e-8, atol=1e-10)
    # constant flow k * (p0 - 0) = 8 into the tank
    assert result["tank.level"][-1] == pytest.approx(12.0, rel=1e-6)
    assert not any("fluid" in name for name in result.names)


def test_reading_a_path_field_is_a_located_error(sources):
    err = sources.error(PORT + """
component Model
  port = FluidPort()
  variable rho::Real
relations
  port.p = 1
  rho = 2 * port.fluid
end
""", "Model", marker="rho = 2 * port.fluid")
    assert "`port.fluid` is a Julia object" in err.message


def test_stream_fields_are_not_supported_yet(sources):
    err = sources.error("""
connector Port
  potential p::Real
  flow q::Real
  stream h::Real
end

component Model
  port = Port()
relations
  port.p = 1
end
""", "Model", marker="stream h")
    assert "`stream` connector fields are not supported yet" in err.message


def test_a_native_parameter_says_dyadc_cannot_compute_with_it(sources):
    err = sources.error("""
type Table = Native

component Model
  parameter data::Table
  variable y::Real
relations
  y = data
end
""", "Model", marker="y = data")
    assert "`data` is a Julia object" in err.message
