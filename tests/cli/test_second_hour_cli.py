"""Issue 28 on the command line: `dyadc --version`; `simulate --events FILE`, the events counted
in the summary line and every written file named; `--vars` patterns; the note on free initial
unknowns printed once per model and only after every option is checked; `check DIR` reporting
every file that does not parse."""
from __future__ import annotations

import pytest

from compiler import __version__
from compiler.cli import main
from tests.dyad_cli import run, write

SWING = """
component Swing
  parameter w::Real = 2
  variable x::Real(units = "m")
  variable y::Real
relations
  initial x = 0
  initial y = 0
  der(x) = 2 * w * cos(w * time)
  der(y) = if x > 1 then 1 else 0
end
"""

FREE = """
component Free
  variable x::Real
  variable v::Real
relations
  der(x) = v
  der(v) = -x
metadata {"Dyad": {"tests": {"one": {"stop": 1, "atol": {"x": 1e-6}, "expect": {"signals": ["x"]}},
                             "two": {"stop": 2, "atol": {"x": 1e-6}, "expect": {"signals": ["x"]}}}}}
end
"""


def test_version(capsys):
    with pytest.raises(SystemExit) as done:
        main(["--version"])
    assert done.value.code == 0
    assert capsys.readouterr().out == f"dyadc {__version__}\n"


def test_events_file_the_count_in_the_summary_and_every_written_file_named(tmp_path, capsys):
    model = write(tmp_path, "Swing.dyad", SWING)
    out = tmp_path / "out"
    code, _, err = run(capsys, "simulate", model, "--stop", 2, "--output", out / "r.csv", "--plot",
                       out / "r.png", "--events", out / "events.csv")
    assert code == 0, err
    summary = err.strip().splitlines()[-1]
    assert " steps, 2 events, compile " in summary
    assert summary.endswith(f"; wrote {out / 'r.csv'}, {out / 'r.csv.json'}, {out / 'r.png'} and "
                            f"{out / 'events.csv'}")
    rows = [line.split(",") for line in (out / "events.csv").read_text().splitlines()]
    assert rows[0] == ["time", "event", "direction"]
    assert [row[1:] for row in rows[1:]] == [["x > 1", "rising"], ["x > 1", "falling"]]


def test_an_events_file_must_be_csv_and_is_checked_before_the_run(tmp_path, capsys, monkeypatch):
    import compiler.pipeline
    monkeypatch.setattr(compiler.pipeline, "compile_or_load", lambda *a, **k: pytest.fail("compiled"))
    code, _, err = run(capsys, "simulate", write(tmp_path, "Swing.dyad", SWING), "--stop", 1, "--events",
                       tmp_path / "events.txt")
    assert code == 1 and "error: --events" in err and "CSV" in err


def test_vars_patterns_choose_the_columns(tmp_path, capsys):
    model = write(tmp_path, "Swing.dyad", SWING)
    code, out, err = run(capsys, "simulate", model, "--stop", 1, "--vars", "?")
    assert code == 0, err
    assert [line.split()[0] for line in out.splitlines()] == ["time", "x", "y"]
    code, _, err = run(capsys, "simulate", model, "--stop", 1, "--vars", "z*")
    assert code == 1 and "error: --vars: the pattern 'z*' matches no signal" in err


def test_the_free_unknowns_note_comes_once_and_only_after_the_options_are_checked(tmp_path, capsys):
    model = write(tmp_path, "Free.dyad", FREE)
    code, _, err = run(capsys, "simulate", model, "--stop", 1, "--vars", "nothing")
    assert code == 1 and "note:" not in err and "unknown signal 'nothing'" in err
    code, _, err = run(capsys, "simulate", model, "--stop", 1, "-p", "x=1m")
    assert code == 1 and "note:" not in err
    code, _, err = run(capsys, "simulate", model, "--stop", 1)
    assert code == 0 and err.count("the initial conditions leave 2 unknown(s) free") == 1, err


def test_the_free_unknowns_note_comes_once_per_model_in_dyadc_test(tmp_path, capsys):
    model = write(tmp_path, "Free.dyad", FREE)
    code, out, _ = run(capsys, "test", model, "--golden", tmp_path / "g", "--accept")
    assert code == 0, out
    assert out.count("the initial conditions leave 2 unknown(s) free") == 1, out


def test_check_dir_reports_every_file_that_does_not_parse(tmp_path, capsys):
    write(tmp_path, "A.dyad", "component A\n  variable x::Real\nrelations\n  x = 2 3\nend\n")
    write(tmp_path, "B.dyad", "component B\n  variable x::Real\nrelations\n  when x > 1 then\nend\n")
    write(tmp_path, "C.dyad", "component C\n  variable x::Real\nrelations\n  der(x) = -x\n  initial x = 1\nend\n")
    code, out, _ = run(capsys, "check", tmp_path)
    assert code == 1
    assert f"{tmp_path / 'A.dyad'}:4:9: error: " in out
    assert f"{tmp_path / 'B.dyad'}:4:3: error: `when` is Modelica" in out
    assert "ok: C (1 equations, 1 unknowns)" in out
