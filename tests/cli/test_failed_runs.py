"""A failed run says where and why, points at the declaration of the variable that failed it, and
writes no output file, or with --keep-partial a file named as partial (issue 14 item 5)."""
from __future__ import annotations

import pytest

from compiler.cli import main

DRAINING = """component Draining
  variable x::Real(min = 0)
relations
  initial x = 1
  der(x) = -1
end
"""


@pytest.fixture
def model(tmp_path):
    path = tmp_path / "Draining.dyad"
    path.write_text(DRAINING, encoding="utf-8")
    return path


def test_a_bound_failure_names_time_value_bound_and_the_declaration(model, tmp_path, capsys):
    out = tmp_path / "out.csv"
    assert main(["simulate", str(model), "--stop", "3", "--output", str(out)]) == 1
    err = capsys.readouterr().err
    assert "left the model's domain at t = 1.0000" in err and "outside its declared min = 0" in err
    assert f"{model}:2:3: note: `x` is declared here" in err
    assert "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["Draining.dyad"]


def test_keep_partial_writes_what_the_run_reached_under_a_partial_name(model, tmp_path, capsys):
    out = tmp_path / "out.csv"
    assert main(["simulate", str(model), "--stop", "3", "--points", "301", "--output", str(out),
                 "--keep-partial"]) == 1
    assert not out.exists()
    rows = (tmp_path / "out.partial.csv").read_text().splitlines()
    assert rows[0] == "time,x"
    last_time, last_x = (float(v) for v in rows[-1].split(","))
    assert last_time == pytest.approx(1.0) and last_x == pytest.approx(0.0, abs=1e-9)   # on the bound
    assert "out.partial.csv" in capsys.readouterr().err
