"""`dyadc check` on a library part that cannot run alone (issue 17 item 7): a balanced component
with open connectors is reported as partial, an unbalanced one names the equation set at fault."""
from __future__ import annotations

from compiler.cli import main

# A gear between two rotational flanges, in our own words: phi_a = ratio * phi_b and the
# torques balance as tau_a * ratio + tau_b = 0 ... the broken variant forgets that second law,
# the over-full one states the kinematics twice.
GEAR = """
connector Shaft
  potential phi::Real
  flow tau::Real
end

component Gear
  parameter ratio::Real = 3
  shaft_a = Shaft()
  shaft_b = Shaft()
relations
  shaft_a.phi = ratio * shaft_b.phi
  LAW
end
"""


def _check(tmp_path, capsys, law: str) -> tuple[int, str, str]:
    path = tmp_path / "Gear.dyad"
    path.write_text(GEAR.replace("LAW", law))
    code = main(["check", f"{path}:Gear"])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_a_balanced_part_is_partial_with_its_open_connectors(tmp_path, capsys):
    code, out, _ = _check(tmp_path, capsys, "ratio * shaft_a.tau + shaft_b.tau = 0")
    assert code == 0
    assert "partial: balanced as a component, 2 open connectors (shaft_a, shaft_b)" in out


def test_a_missing_law_names_what_nothing_determines(tmp_path, capsys):
    code, _, err = _check(tmp_path, capsys, "")
    assert code == 1 and "Traceback" not in err
    assert "component `Gear` is unbalanced: 1 equation(s) for 2 unknown(s)" in err
    assert "under-determined: nothing determines all of" in err and "tau" in err


def test_a_doubled_law_names_the_over_determined_equations(tmp_path, capsys):
    code, _, err = _check(tmp_path, capsys, "ratio * shaft_a.tau + shaft_b.tau = 0\n"
                                            "  shaft_b.phi = shaft_a.phi / ratio")
    assert code == 1
    assert "component `Gear` is unbalanced: 3 equation(s) for 2 unknown(s)" in err
    assert "over-determined:" in err and "Gear.dyad:" in err
