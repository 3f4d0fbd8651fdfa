"""`dyadc run ANALYSIS` (issue 17): a Dyad `analysis` block extending TransientAnalysis runs its
model with the analysis's modifiers, span, tolerances, saveat and dtmax, and writes the result;
other analysis kinds are refused with a located error."""
from __future__ import annotations

import csv
import math

import numpy as np
import pytest

from compiler.cli import main

# An RC discharge written in our own words: v' = -v / (R C), v(0) = v0; i = v / R.
LIBRARY = '''
component Discharge
  parameter R::Real = 1
  parameter C::Real = 1
  parameter v0::Real = 1
  variable v::Real
  variable i::Real
relations
  initial v = v0
  C * der(v) = -i
  v = R * i
end

analysis Quick
  extends TransientAnalysis(stop = 2, abstol = 1e-9, reltol = 1e-9)
  parameter tau::Real = 0.5
  model = Discharge(R = tau / 2, C = 2, v0 = 3)
end

"A typed model field and a sampled output."
analysis Sampled
  extends TransientAnalysis(alg = "auto", start = 0, stop = 1, saveat = 0.25, dtmax = 0.01,
                            reltol = 1m, abstol = 1u)
  model::Discharge = Discharge()
end

partial analysis Base
  extends TransientAnalysis(stop = 1, reltol = 1e-8, abstol = 1e-10)
  parameter k::Real = 2
end

analysis Derived
  extends Base(stop = 3)
  model = Discharge(R = k)
end

analysis Steady
  extends SteadyStateAnalysis(abstol = 1e-6)
  model = Discharge()
end

analysis NoStop
  extends TransientAnalysis(reltol = 1e-6)
  model = Discharge()
end

analysis Misspelt
  extends TransientAnalysis(stop = 1, reltoll = 1e-6)
  model = Discharge()
end

analysis Backwards
  extends TransientAnalysis(start = 2, stop = 1)
  model = Discharge()
end
'''


@pytest.fixture
def library(tmp_path, monkeypatch):
    path = tmp_path / "Runs.dyad"
    path.write_text(LIBRARY)
    monkeypatch.chdir(tmp_path)
    return path


def _table(path) -> dict[str, np.ndarray]:
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    return {name: np.array([float(r[k]) for r in rows[1:]]) for k, name in enumerate(rows[0])}


def _line(path, text: str) -> int:
    return next(n for n, line in enumerate(path.read_text().splitlines(), 1) if text in line)


def test_run_writes_the_result_csv_named_after_the_analysis(library, capsys):
    assert main(["run", f"{library}:Quick"]) == 0
    table = _table(library.parent / "Quick.csv")
    tau = 0.25 * 2                                     # R C with the analysis's modifiers
    t = table["time"]
    assert t[0] == 0 and t[-1] == 2 and len(t) == 501
    np.testing.assert_allclose(table["v"], 3 * np.exp(-t / tau), rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(table["i"], table["v"] / 0.25, rtol=1e-12)
    err = capsys.readouterr().err
    assert "ran Quick (Discharge from 0 to 2 s, reltol 1e-09, abstol 1e-09)" in err


def test_saveat_dtmax_typed_model_field_and_output_option(library):
    assert main(["run", f"{library}:Sampled", "--output", "out/s.csv", "--vars", "v"]) == 0
    table = _table(library.parent / "out" / "s.csv")
    np.testing.assert_allclose(table["time"], [0, 0.25, 0.5, 0.75, 1.0], atol=1e-15)
    assert list(table) == ["time", "v"]
    np.testing.assert_allclose(table["v"], np.exp(-table["time"]), rtol=1e-4)


def test_analysis_parameters_and_overrides_reach_the_model(library):
    assert main(["run", f"{library}:Derived", "-p", "k=4", "--output", "d.csv"]) == 0
    table = _table(library.parent / "d.csv")
    assert table["time"][-1] == 3                      # Derived's stop replaces Base's
    assert table["v"][-1] == pytest.approx(math.exp(-3 / 4), rel=1e-6)
    assert main(["run", f"{library}:Derived", "-p", "C=0.5", "--output", "e.csv"]) == 0
    assert _table(library.parent / "e.csv")["v"][-1] == pytest.approx(math.exp(-3 / 1), rel=1e-6)


def test_a_qualified_name_on_the_library_path(tmp_path, monkeypatch):
    package = tmp_path / "lib" / "MyRuns"
    package.mkdir(parents=True)
    (package / "Runs.dyad").write_text(LIBRARY)
    monkeypatch.chdir(tmp_path)
    assert main(["run", "MyRuns.Quick", "-L", str(tmp_path / "lib")]) == 0
    assert (tmp_path / "Quick.csv").is_file()


@pytest.mark.parametrize("name, words", [
    ("Steady", "analysis `Steady` is a `SteadyStateAnalysis`: dyadc runs `TransientAnalysis` "
               "analyses only"),
    ("NoStop", "analysis `NoStop` gives no stop time"),
    ("Misspelt", "`TransientAnalysis` has no field `reltoll`"),
    ("Backwards", "`stop` of analysis `Backwards` (1) must be after start (2)"),
    ("Base", "analysis `Base` is partial"),
    ("Nothing", "no analysis `Nothing` in"),
    ("Discharge", "no analysis `Discharge` in"),
])
def test_analyses_dyadc_cannot_run_are_located_errors(library, capsys, name, words):
    assert main(["run", f"{library}:{name}"]) == 1
    err = capsys.readouterr().err
    assert words in err and "Traceback" not in err
    if name not in ("Nothing", "Discharge"):              # at the analysis or its extends line
        header = _line(library, f"analysis {name}")
        assert any(f"Runs.dyad:{line}:" in err.splitlines()[0] for line in (header, header + 1))
    assert not list(library.parent.glob("*.csv"))


GUARDED = '''
analysis Huge
  extends TransientAnalysis(stop = 9^9^9)
  model = Discharge()
end

analysis Circular
  extends TransientAnalysis(stop = a)
  parameter a::Real = 2 * b
  parameter b::Real = a
  model = Discharge()
end

analysis Worded
  extends TransientAnalysis(stop = "ten")
  model = Discharge()
end
'''


def test_analysis_fields_go_through_the_guarded_evaluator(library):
    """`stop = 9^9^9` is refused at once, as the same expression in a parameter is, at the power
    (in a subprocess with a timeout: an unguarded evaluator folds 9^(9^9) exactly for minutes)."""
    import subprocess
    import sys
    library.write_text(LIBRARY + GUARDED)
    done = subprocess.run([sys.executable, "-m", "compiler", "run", f"{library}:Huge"],
                          capture_output=True, text=True, timeout=60, cwd=library.parent)
    assert done.returncode == 1
    first = done.stderr.splitlines()[0]
    line = _line(library, "stop = 9^9^9")
    column = library.read_text().splitlines()[line - 1].index("9^9^9") + 1
    assert first.endswith(f"Runs.dyad:{line}:{column}: error: the power 9^387420489 is too large: "
                          f"about 10^369,693,099, beyond a 64-bit float (at most about 1.8e308)")
    assert "Traceback" not in done.stderr


@pytest.mark.parametrize("name, words, at", [
    ("Circular", "analysis parameters refer to each other in a cycle", "parameter b::Real = a"),
    ("Worded", "`stop` of analysis `Worded` must be a number", 'stop = "ten"'),
])
def test_bad_analysis_fields_are_located_errors(library, capsys, name, words, at):
    library.write_text(LIBRARY + GUARDED)
    assert main(["run", f"{library}:{name}"]) == 1
    first = capsys.readouterr().err.splitlines()[0]
    assert first.endswith(f"error: {words}")
    assert f"Runs.dyad:{_line(library, at)}:" in first
