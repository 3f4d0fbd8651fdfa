"""Each kind of unit mismatch of issue 26, item 1, is caught and located: the message names both
units, the caret is on the mismatching term, the notes give each term's unit in SI base form."""
from __future__ import annotations

import pytest

HEAD = """
component Model
  parameter R::Resistance = 2
  parameter L0::Inductance = 0.5
  variable v::Voltage
  variable i::Current
  variable x::Length
  variable s::Velocity
  variable F::Force
  variable A::Area
"""


def first_line(error: str) -> str:
    return error.splitlines()[0]


def test_volts_plus_amperes_is_located_at_the_ampere_term(units):
    text = HEAD + "relations\n  v = 1 + i\n  der(x) = s\n  F = 0\n  A = x^2\nend\n"
    error = units.error(text)
    path = units.root / "Model.dyad"
    line = units.line_of(text, "v = 1 + i")
    assert first_line(error) == (f"{path}:{line}:11: error: units do not match in this equation: "
                                 "left side V, right side A")
    assert "`v` is V (kg.m2/(s3.A))" in error and "`i` is A" in error
    assert error.splitlines()[2] == "              ^"        # under `i`, not `1`
    assert "hint: " in error


def test_resistor_given_an_inductance_is_located_at_the_modifier(units):
    text = """
    component Motor
      parameter Lm::Inductance = 0.5
      r = ElectricalComponents.Resistor(R = Lm)
      g = ElectricalComponents.Ground()
    relations
      connect(r.n, g.g)
    end
    """
    error = units.error(text)
    line = units.line_of(text, "Resistor(R = Lm)")
    assert first_line(error) == (f"{units.root / 'Model.dyad'}:{line}:41: error: units do not match "
                                 "in this binding: `R` Ohm, its value H")
    assert "`R` is Ohm (kg.m2/(s3.A2))" in error and "`Lm` is H (kg.m2/(s2.A2))" in error
    assert "parameter R::Resistance" in error           # the note shows the declaration, not its doc
    assert "note: in `r`" in error


CASES = {
    "two terms of one side": ("  0 = v + i\n", "0 = v + i", "units do not match in this equation: first term V, this term A"),
    "a term of a sum": ("  v = R * (i + v)\n", "R * (i + v)", "units do not match in this sum: first term A, this term V"),
    "a parameter default": ("  v = R * i\n", "parameter R::Resistance = L0",
                            "units do not match in this binding: `R` Ohm, its value H"),
    "a variable binding": ("  v = R * i\n", "variable w::Voltage = i",
                           "units do not match in this binding: `w` V, its value A"),
    "an attribute value": ("  v = R * i\n", "variable q::Voltage(guess = L0)",
                           "units do not match in this binding: the guess of `q` V, its value H"),
    "der": ("  der(x) = F\n", "der(x) = F", "units do not match in this equation: left side m/s, right side N"),
    "a function argument": ("  v = R * i * exp(x)\n", "exp(x)",
                            "the argument of `exp` must be dimensionless, but its unit is m"),
    "sqrt": ("  s = sqrt(A)\n", "sqrt(A)", "units do not match in this equation: left side m/s, right side m"),
    "a constant power": ("  A = x ^ 3\n", "x ^ 3", "units do not match in this equation: left side m2, right side m3"),
    "if branches": ("  x = if time > 1 then x else s\n", "then x else s",
                    "units do not match in the branches of this `if`: the `then` branch m, the `else` branch m/s"),
    "ifelse branches": ("  x = ifelse(time > 1, x, s)\n", "ifelse(time > 1, x, s)",
                        "units do not match in the branches of this `if`: the `then` value m, the `else` value m/s"),
    "min and max": ("  x = max(x, s)\n", "max(x, s)",
                    "units do not match in the arguments of this call: first argument m, this argument m/s"),
    "a comparison": ("  x = ifelse(x > s, x, 0)\n", "x > s",
                     "units do not match in this comparison: the left side m, the right side m/s"),
    "array elements": ("  p = [x, s]\n", "[x, s]",
                       "units do not match in this array: first element m, this element m/s"),
}


@pytest.mark.parametrize("kind", sorted(CASES))
def test_each_kind_of_mismatch_is_caught(units, kind):
    relation, marker, message = CASES[kind]
    declarations = "  variable w::Voltage = i\n" if kind == "a variable binding" else ""
    declarations += "  variable q::Voltage(guess = L0)\n" if kind == "an attribute value" else ""
    declarations += "  variable p::Length[2]\n" if kind == "array elements" else ""
    head = HEAD.replace("= 2\n", "= L0\n") if kind == "a parameter default" else HEAD
    text = head + declarations + "relations\n" + relation + "end\n"
    findings = units.findings(text)
    assert [f.message for f in findings] == [message]
    span = findings[0].span
    assert span.file.endswith("Model.dyad") and span.line == units.line_of(text, marker)


def test_connecting_signals_of_different_units_is_caught(units):
    text = """
    component Model
      a = RealOutput(units = "m")
      b = RealInput(units = "V")
    relations
      connect(a, b)
      a = 1
    end
    """
    findings = units.findings(text)
    assert [f.message for f in findings] == ["units do not match in this connection: `a` m, `b` V"]
    assert findings[0].span.line == units.line_of(text, "connect(a, b)")


def test_connecting_physical_connectors_compares_each_potential_and_flow(units):
    text = """
    connector Mech
      potential x::Length
      flow f::Force
    end
    connector Elec
      potential x::Voltage
      flow f::Current
    end
    component Model
      a = Mech()
      b = Elec()
    relations
      connect(a, b)
    end
    """
    messages = [f.message for f in units.findings(text)]
    assert messages == ["units do not match in this connection: `a.x` m, `b.x` V",
                        "units do not match in this connection: `a.f` N, `b.f` A"]


def test_millimetres_against_metres_name_the_factor(units):
    text = """
    component Model
      variable x::Length
      variable x_mm::Real(units = "mm")
    relations
      der(x) = 1
      x_mm = x
    end
    """
    findings = units.findings(text)
    assert [f.message for f in findings] == [
        "units do not match in this equation: left side mm, right side m: the same "
        "dimension, but they differ by a factor of 0.001"]


def test_a_temperature_in_degrees_celsius_cannot_enter_an_equation(units):
    text = """
    component Model
      parameter T0::Temp_C = 20
      variable T::Temperature
    relations
      T = T0
    end
    """
    findings = units.findings(text)
    assert [f.message for f in findings] == [
        "`T0` is declared in `degC`, a unit with an offset, and cannot be used in an equation"]
    assert "-p" in findings[0].hint


def test_a_conflict_among_inferred_units_is_an_error(units):
    text = """
    component Model
      variable v::Voltage
      variable i::Current
      variable z::Real
    relations
      z = v
      z = i
      v = time * 1
    end
    """
    findings = units.findings(text)
    assert [f.message for f in findings][:1] == ["units do not match in this equation: left side V, right side A"]
    assert any("inferred here" in text for text, _ in findings[0].notes)
