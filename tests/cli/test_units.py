"""compiler.units.system: the unit strings of the library and of `-p NAME=VALUE UNIT` read and convert."""
import math
import re
from pathlib import Path

import pytest

from compiler.units.system import UnitError, conversion_factor, parse_unit

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("given, declared, factor", [
    ("mm", "m", 1e-3),
    ("km", "m", 1e3),
    ("g", "kg", 1e-3),
    ("t", "kg", 1e3),
    ("kN/m", "N/m", 1e3),
    ("N/mm", "N/m", 1e3),
    ("bar", "Pa", 1e5),
    ("MPa", "Pa", 1e6),
    ("L/min", "m3/s", 1e-3 / 60),
    ("cm2", "m2", 1e-4),
    ("g.cm2", "kg.m2", 1e-7),
    ("kg.m/s2", "N", 1.0),
    ("N.m", "J", 1.0),
    ("deg", "rad", math.pi / 180),
    ("rpm", "rad/s", 2 * math.pi / 60),
    ("mA", "A", 1e-3),
    ("kOhm", "Ohm", 1e3),
    ("uF", "F", 1e-6),
    ("µF", "F", 1e-6),
    ("min", "s", 60.0),
    ("ms", "s", 1e-3),
    ("1/min", "Hz", 1 / 60),
    ("m.s-2", "m/s2", 1.0),
    ("m^2", "m2", 1.0),
    ("kg*m**2", "kg.m2", 1.0),
    ("W/(m.K)", "W/m/K", 1.0),
    ("N m s / rad", "N.m.s/rad", 1.0),
    ("%", "1", 0.01),
])
def test_consistent_units_convert_by_their_factor(given, declared, factor):
    assert conversion_factor(given, declared) == pytest.approx(factor, rel=1e-14)


@pytest.mark.parametrize("given, declared", [
    ("kg", "m"), ("m", "m2"), ("N", "N/m"), ("Hz", "rad/s"), ("s", "1"), ("Pa", "N"), ("rad", "1"),
])
def test_units_of_different_kinds_are_refused_with_both_dimensions(given, declared):
    with pytest.raises(UnitError) as err:
        conversion_factor(given, declared)
    assert f"`{given}`" in str(err.value) and f"`{declared}`" in str(err.value)
    assert "different kinds" in str(err.value)


@pytest.mark.parametrize("text, words", [
    ("furlong", "unknown unit `furlong`"),
    ("m/", "ends where a unit symbol is expected"),
    ("(m.s", "unclosed"),
    ("2m", "a number `2`"),
    ("m^", "exponent is missing"),
    ("degC", "offset"),
    ("m$", "unexpected `$`"),
    ("", "empty unit"),
])
def test_unreadable_units_say_what_is_wrong(text, words):
    with pytest.raises(UnitError, match=re.escape(words)):
        parse_unit(text)


def test_whole_symbols_win_over_prefix_readings():
    assert parse_unit("min").factor == 60.0            # minute, not milli-inch
    assert parse_unit("Pa").dimension() == "kg/(m.s2)"  # pascal, not peta-year
    assert parse_unit("cd").dimension() == "cd"        # candela, not centi-day
    assert parse_unit("h").factor == 3600.0            # hour, not hecto
    assert parse_unit("T").factor == 1.0               # tesla, not tera
    assert parse_unit("dam").factor == 10.0            # deca before deci


def test_every_unit_the_standard_library_declares_is_readable():
    declared = set()
    for source in (ROOT / "components").rglob("*.dyad"):
        declared.update(re.findall(r'units\s*=\s*"([^"]*)"', source.read_text(encoding="utf-8")))
    assert {"m", "kg", "N.m.s/rad", "kg.m2", "m/s2", "Ohm"} <= declared
    for unit in declared:
        try:
            parse_unit(unit)
        except UnitError as err:        # only units with an offset may be refused, and say so
            assert "offset" in str(err), (unit, err)


def test_a_unit_with_an_offset_converts_only_to_itself():
    assert conversion_factor("degC", "degC") == 1.0
    with pytest.raises(UnitError, match="offset"):
        conversion_factor("degC", "K")


def test_a_temperature_in_degrees_celsius_sets_a_kelvin_parameter(tmp_path, capsys):
    from compiler.cli import run_command
    model = tmp_path / "Heated.dyad"
    model.write_text("component Heated\n  parameter T0::Temperature = 300\n  variable T::Temperature\n"
                     "relations\n  T = T0\nend\n")
    out = tmp_path / "out.csv"
    assert run_command(["simulate", str(model), "--stop", "0.1", "-p", "T0=20degC",
                        "--output", str(out)]) == 0
    header, first = out.read_text().splitlines()[:2]
    assert float(first.split(",")[header.split(",").index("T")]) == pytest.approx(293.15, abs=1e-9)


def test_conversions_and_the_unit_check_read_units_with_one_parser():
    from compiler.units import system
    assert system.parse_unit("N.m/A").consistent_with(system.parse_unit("V.s/rad"))
    assert conversion_factor("kN.m", "N.m") == pytest.approx(1e3)
