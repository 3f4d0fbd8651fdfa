"""`make compat` runs every model command with `--units warn` (issue 26, item 7): a published
component whose units do not match still counts as checked, and the report lists the mismatch at
its published line in a column and a section of its own. Measured on a two-file local corpus."""
from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
import compat  # noqa: E402

BAD = """\
"Volts plus amperes"
component Bad
  variable v::Voltage
  variable i::Current
relations
  v = 1 + i
  i = 2
end
"""

GOOD = """\
"Ohm's law"
component Good
  parameter R::Resistance = 2
  variable v::Voltage
  variable i::Current
relations
  v = R * i
  i = 2
end
"""


def test_unit_findings_have_their_own_column_and_do_not_lower_the_check_rate(tmp_path):
    repository = tmp_path / "corpus" / "UnitsDemo"
    (repository / "dyad").mkdir(parents=True)
    (repository / "Project.toml").write_text('name = "UnitsDemo"\n')
    (repository / "LICENSE").write_text("MIT License\n")
    (repository / "dyad" / "Bad.dyad").write_text(BAD)
    (repository / "dyad" / "Good.dyad").write_text(GOOD)
    report = tmp_path / "compatibility.md"
    assert compat.main([str(tmp_path / "corpus"), "--output", str(report), "--jobs", "2"]) == 0
    text = report.read_text()
    assert "| components checked | 2 / 2 | 100% | 90% | yes |" in text
    assert "| components with unit findings (`--units warn`; not counted against the rates) | 1 / 2 | 50% | | |" in text
    assert ("| UnitsDemo/dyad/Bad.dyad:6 | units do not match in this equation: left side V, "
            "right side A | Bad |") in text
    assert "| UnitsDemo/dyad/Bad.dyad | yes | 1 / 1 | 0 / 0 | 0 / 0 | 1 |" in text
    assert "| UnitsDemo/dyad/Good.dyad | yes | 1 / 1 | 0 / 0 | 0 / 0 | 0 |" in text
