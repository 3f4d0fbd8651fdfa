"""Well-formed patterns of issue 26, items 2-4, give no unit message: angles are dimensionless,
literals and `::Real` declarations take the unit their context demands (per instance), prefixes
that agree are consistent."""
from __future__ import annotations

import pytest

from compiler.units.system import convert_value, parse_unit

SILENT = {
    "a model written without units": """
    component Model
      variable x::Real
      variable v::Real
    relations
      der(x) = v + log(x)
      der(v) = -x
    end
    """,
    "a function of time alone": """
    component Model
      variable y::Real
    relations
      y = sin(time) + exp(-time) + cos(2 * time)
    end
    """,
    "an EMF with a torque constant in N.m/A and a speed in rad/s": """
    component Model
      parameter k::Real(units = "N.m/A") = 0.1
      variable w::AngularVelocity
      variable v::Voltage
      variable i::Current
      variable tau::Torque
    relations
      v = k * w
      tau = k * i
      der(w) = tau / 0.01
      v = 2 * i
    end
    """,
    "a frequency in Hz turned into an angular velocity": """
    component Model
      parameter f::Frequency = 50
      variable w::AngularVelocity
      variable phi::Angle
    relations
      w = 2 * pi * f
      der(phi) = w
    end
    """,
    "literals in a first-order lag": """
    component Model
      parameter tau::Real = 0.5
      variable x::Real
    relations
      der(x) = -x / tau + 0.1
    end
    """,
    "literals in an affine map of one unit": """
    component Model
      variable x::Length
      variable y::Length
    relations
      x = 0.5 * time
      y = 2 * x + 1
    end
    """,
    "a generic gain carrying volts in one place and amperes in another": """
    component Model
      g1 = BlockComponents.Gain(k = 2)
      g2 = BlockComponents.Gain(k = 3)
      parameter w::AngularVelocity = 3
      variable v::Voltage
      variable i::Current
    relations
      g1.u = v
      g2.u = i
      v = 5 * sin(w * time)
      i = 0.1 * cos(w * time)
    end
    """,
    "prefixed units that agree": """
    component Model
      variable a::Real(units = "kN")
      variable b::Real(units = "kg.km/s2")
      variable c::Real(units = "m/s2")
      variable d::Real(units = "mm/ms2")
    relations
      a = b
      b = 3 * time
      c = d * 1
      d = 4 * time
    end
    """,
    "the power of a constant exponent and a square root": """
    component Model
      variable x::Length
      variable A::Area
      variable V::Volume
      variable L::Length
    relations
      x = 2 * time
      A = x ^ 2
      V = x * A
      L = sqrt(A) + V ^ (1/3)
    end
    """,
}


@pytest.mark.parametrize("name", sorted(SILENT))
def test_well_formed_patterns_give_no_unit_message(units, name):
    assert units.findings(SILENT[name]) == []


def test_the_dc_motor_of_the_library_checks_with_its_units():
    from compiler.model.flatten import flatten_model
    flat = flatten_model("ElectricalComponents.Resistor")
    assert flat.unit_findings == []


def test_an_angle_is_dimensionless_in_the_check_but_not_converted_from_a_frequency():
    assert parse_unit("rad/s").consistent_with(parse_unit("Hz"))
    with pytest.raises(ValueError, match="different kinds"):
        convert_value(10, "Hz", "rad/s")


def test_offset_temperatures_convert_as_absolute_temperatures():
    assert convert_value(20, "degC", "K") == pytest.approx(293.15, abs=1e-12)
    assert convert_value(68, "degF", "degC") == pytest.approx(20, abs=1e-12)
    assert convert_value(300, "K", "degC") == pytest.approx(26.85, abs=1e-12)
    assert convert_value(1, "mK", "K") == pytest.approx(1e-3)


GENERIC_BLOCKS = """
component Model
  parameter w::AngularVelocity = 3
  on_volts = BlockComponents.Feedback()
  on_amperes = BlockComponents.Feedback()
  variable v::Voltage
  variable i::Current
relations
  on_volts.u1 = v
  on_volts.u2 = 2 * v
  on_amperes.u1 = i
  on_amperes.u2 = SECOND
  v = 5 * sin(w * time)
  i = 0.1 * cos(w * time)
end
"""


def test_a_generic_block_takes_its_units_per_instance(units):
    assert units.findings(GENERIC_BLOCKS.replace("SECOND", "i")) == []


def test_a_generic_block_fed_volts_and_amperes_is_located_in_the_block(units):
    findings = units.findings(GENERIC_BLOCKS.replace("SECOND", "v"))
    assert [f.message for f in findings] == [
        "units do not match in this equation: left side A, right side V"]
    assert findings[0].span.file.endswith("BlockComponents/Math/Feedback.dyad")
    assert findings[0].paths == ["on_amperes"]
