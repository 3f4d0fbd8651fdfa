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


def test_a_bound_left_is_a_warning_and_the_run_goes_on(model, tmp_path, capsys):
    # Dyad's and Modelica's reading of min/max (issue 17 item 5): checked, not enforced
    out = tmp_path / "out.csv"
    assert main(["simulate", str(model), "--stop", "3", "--output", str(out)]) == 0
    err = capsys.readouterr().err
    warnings = [line for line in err.splitlines() if line.startswith("warning: ")]
    assert len(warnings) == 1 and "x = -1e-06 left its declared min = 0 at t = 1.0000" in warnings[0]
    assert "--strict-bounds" in warnings[0] and "Traceback" not in err
    last_time, last_x = (float(v) for v in out.read_text().splitlines()[-1].split(","))
    assert last_time == 3.0 and last_x == pytest.approx(-2.0, abs=1e-9)


def test_a_bound_failure_names_time_value_bound_and_the_declaration(model, tmp_path, capsys):
    out = tmp_path / "out.csv"
    assert main(["simulate", str(model), "--stop", "3", "--strict-bounds", "--output", str(out)]) == 1
    err = capsys.readouterr().err
    assert "left the model's domain at t = 1.0000" in err and "outside its declared min = 0" in err
    assert f"{model}:2:3: note: `x` is declared here" in err
    assert "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["Draining.dyad"]


def test_keep_partial_writes_what_the_run_reached_under_a_partial_name(model, tmp_path, capsys):
    out = tmp_path / "out.csv"
    assert main(["simulate", str(model), "--stop", "3", "--points", "301", "--output", str(out),
                 "--keep-partial", "--strict-bounds"]) == 1
    assert not out.exists()
    rows = (tmp_path / "out.partial.csv").read_text().splitlines()
    assert rows[0] == "time,x"
    last_time, last_x = (float(v) for v in rows[-1].split(","))
    assert last_time == pytest.approx(1.0) and last_x == pytest.approx(0.0, abs=1e-9)   # on the bound
    assert "out.partial.csv" in capsys.readouterr().err


def test_a_sign_error_that_makes_the_solution_explode_stops_with_a_located_error(tmp_path, capsys):
    # meant der(x) = -10 x; with the sign wrong x grows as exp(10 t): 2.7e43 at t = 10
    path = tmp_path / "Runaway.dyad"
    path.write_text("""component Runaway
  variable x::Real
relations
  initial x = 1
  der(x) = 10 * x
end
""", encoding="utf-8")
    assert main(["simulate", str(path), "--stop", "10", "--output", str(tmp_path / "out.csv")]) == 1
    err = capsys.readouterr().err
    assert "grew beyond 1e+12 times its scale" in err and "the model diverges" in err
    t = float(err.split("stopped at t = ")[1].split(":")[0])
    assert 2.7 < t < 3.0                    # exp(10 t) passes 1e12 at t = 2.76
    assert f"{path}:2:3: note: `x` is declared here" in err
    assert not (tmp_path / "out.csv").exists()
