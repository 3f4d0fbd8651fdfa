"""Issue 28, errors of a newcomer's second hour: every location at the declaration (never at its
doc string), `check` and `simulate` agreeing on a parameter without a value (its hint in the
declared type, a note where the component is instantiated)."""
from __future__ import annotations

import re
from pathlib import Path

from tests.dyad_cli import GROUND, PIN, line_of, resistor, resistor_circuit, run, voltage_source, write

TYPES = ('type Resistance = Real(units = "Ohm")\n' + PIN
         + resistor("""
             "Resistance"
             parameter R::Resistance
             """)
         + GROUND + voltage_source(1)
         + resistor_circuit("connect(source.p, resistor.p)", "connect(resistor.n, source.n, ground.g)"))

RUNAWAY = """
component Runaway
  "Angular velocity"
  variable w::Real
relations
  der(w) = w
  initial w = 1
end
"""


def located_lines(err: str, path: Path) -> list[tuple[str, int]]:
    """(kind, line) of every `FILE:LINE:COL: error|note:` in `err` that is in `path`."""
    return [(m.group(3), int(m.group(2))) for m in re.finditer(r"^(.*):(\d+):\d+: (error|note): ", err,
                                                                re.MULTILINE)
            if Path(m.group(1)).resolve() == path.resolve()]


def test_check_and_simulate_refuse_a_missing_value_alike_at_the_declaration(tmp_path, capsys):
    path = write(tmp_path, "Circuit.dyad", TYPES)
    spec = f"{path}:Circuit"
    check_code, _, check_err = run(capsys, "check", spec)
    simulate_code, _, simulate_err = run(capsys, "simulate", spec, "--stop", "1")
    assert (check_code, simulate_code) == (1, 1), check_err + simulate_err
    for err in (check_err, simulate_err):
        # the declaration, not its doc string one line above; the instantiation as a note
        assert located_lines(err, path)[:2] == [("error", line_of(path, "parameter R::")),
                                                ("note", line_of(path, "resistor = Resistor()"))], err
        assert "`resistor.R`" in err and "has no value" in err
        assert "R = VALUE" in err and "-p resistor.R=VALUE" in err
    assert check_err.split("\n", 1)[0] == simulate_err.split("\n", 1)[0]


def test_the_hint_for_a_parameter_of_the_model_itself_uses_its_declared_type(tmp_path, capsys):
    path = write(tmp_path, "Decay.dyad", """
        type Rate = Real(units = "1/s")
        component Decay
          "Decay rate"
          parameter k::Rate
          variable x::Real
        relations
          der(x) = -k * x
          initial x = 1
        end
        """)
    code, _, err = run(capsys, "simulate", f"{path}:Decay", "--stop", "1")
    assert code == 1
    assert located_lines(err, path) == [("error", line_of(path, "parameter k::"))], err
    assert "`parameter k::Rate = VALUE`" in err and "::Real" not in err


def test_check_leaves_a_components_own_parameter_to_whoever_uses_it(tmp_path, capsys):
    """A library part (a gain with its `k`) checks alone: its own parameter gets its value where
    the part is used, or from -p; `check` warns at the declaration and exits 0, `simulate` refuses."""
    path = write(tmp_path, "Gain.dyad", """
        component Gain
          "The gain"
          parameter k::Real
          u = RealInput()
          y = RealOutput()
        relations
          y = k * u
        end
        component Alone
          parameter rate::Real
          variable x::Real
        relations
          der(x) = -rate * x
          initial x = 1
        end
        component Rig
          g = Gain()
          variable x::Real
        relations
          g.u = 1
          der(x) = g.y
          initial x = 0
        end
        """)
    code, out, err = run(capsys, "check", f"{path}:Gain")
    assert code == 0, err
    assert "partial" in out
    code, out, err = run(capsys, "check", f"{path}:Alone")
    assert code == 0, err
    assert f"{path}:{line_of(path, 'parameter rate::')}:3: parameter `rate` has no value" in out
    code, _, err = run(capsys, "simulate", f"{path}:Alone", "--stop", "1")
    assert code == 1 and "`rate`" in err and "has no value" in err
    code, _, err = run(capsys, "check", f"{path}:Rig")
    assert code == 1
    assert located_lines(err, path)[:2] == [("error", line_of(path, "parameter k::")),
                                            ("note", line_of(path, "g = Gain()"))], err


def test_a_runaway_variable_is_pointed_at_its_declaration_not_its_doc_string(tmp_path, capsys):
    path = write(tmp_path, "Runaway.dyad", RUNAWAY)
    code, _, err = run(capsys, "simulate", str(path), "--stop", "40", "--no-cache")
    assert code == 1
    assert ("note", line_of(path, "variable w::")) in located_lines(err, path), err
    assert '"Angular velocity"' not in err


def test_a_misspelt_component_gets_a_component_suggested_not_a_quantity_type(tmp_path, capsys):
    path = write(tmp_path, "Motor.dyad", """
        component Motor
          resistor = ElectricalComponents.Resistr(R = 1)
          ground = ElectricalComponents.Ground()
        relations
          connect(resistor.p, resistor.n, ground.g)
        end
        """)
    code, _, err = run(capsys, "check", str(path))
    assert code == 1
    assert "unknown component type `ElectricalComponents.Resistr`" in err
    assert err.rstrip().endswith("hint: did you mean `ElectricalComponents.Resistor`?"), err


def test_an_unqualified_misspelt_component_is_matched_among_the_files_components(tmp_path, capsys):
    text = TYPES.replace("resistor = Resistor()", "resistor = Resistr(R = 1)")
    path = write(tmp_path, "Circuit.dyad", text.replace("type Resistance", "type Resistr_"))
    code, _, err = run(capsys, "check", f"{path}:Circuit")
    assert code == 1
    assert err.rstrip().endswith("hint: did you mean `Resistor`?"), err


def test_modelica_pre_and_edge_are_answered_with_what_dyad_offers(tmp_path, capsys):
    for word in ("pre", "edge"):
        path = write(tmp_path, f"Uses_{word}.dyad", f"""
            component Uses_{word}
              variable x::Real
              variable y::Real
            relations
              der(x) = -x
              y = {word}(x)
            end
            """)
        code, _, err = run(capsys, "check", str(path))
        assert code == 1
        assert located_lines(err, path) == [("error", line_of(path, f"{word}(x)"))], err
        assert f"`{word}` is Modelica" in err and "ifelse(" in err and "unknown function" not in err


DOCUMENTED_PARTIAL = '''"""
A voltage source to be connected: both pins open.
"""
component OpenSource
  p = Pin()
  n = Pin()
  variable v::Real
relations
  v = p.v - n.v
  p.i + n.i = 0
  v = 1
end
'''


def test_a_documented_definition_is_located_at_its_name_not_its_doc_string(tmp_path, capsys):
    path = write(tmp_path, "OpenSource.dyad", PIN + DOCUMENTED_PARTIAL)
    code, _, err = run(capsys, "simulate", f"{path}:OpenSource", "--stop", "1")
    assert code == 1, err
    assert located_lines(err, path)[0] == ("error", line_of(path, "component OpenSource")), err
    assert "is a partial model" in err.splitlines()[0], err


def test_an_unknown_modifier_with_no_close_name_lists_the_parameters(tmp_path, capsys):
    circuit = TYPES.replace("parameter R::Resistance", "parameter R::Resistance = 1.0") \
        .replace("resistor = Resistor()", "resistor = Resistor(f = 2.0)")
    path = write(tmp_path, "Circuit.dyad", circuit)
    code, _, err = run(capsys, "check", f"{path}:Circuit")
    assert code == 1 and "`Resistor` has no parameter, variable or component `f`" in err, err
    assert "hint: the parameters of `Resistor`: `R`" in err, err
