"""The `dyadc` command-line contract: exit codes, messages, CSV format, atomic outputs."""
import csv
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
MODELS = ROOT / "tests" / "models"

OSCILLATOR = """\
component Oscillator
  parameter k::Real = 4.0
  parameter m::Real = 1.0
  variable x::Real(initial = 1.0)
  variable v::Real(initial = 0.0)
relations
  der(x) = v
  m * der(v) = -k * x
end
"""

# 0 = z^2 + time - 1 has no real solution after t = 1: IDAS must fail near there
DOOMED = """\
component Doomed
  variable x::Real(initial = 0.0)
  variable z::Real(guess = 1.0)
relations
  der(x) = z
  z^2 + time - 1 = 0
end
"""


def dyadc(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "compiler", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd or ROOT, timeout=300)


@pytest.fixture
def oscillator(tmp_path):
    path = tmp_path / "Oscillator.dyad"
    path.write_text(OSCILLATOR)
    return path


def test_simulate_writes_the_csv_contract(oscillator, tmp_path):
    out = tmp_path / "res" / "osc.csv"
    run = dyadc("simulate", oscillator, "--stop", 1.0, "--points", 11, "--rtol", 1e-10, "--atol", 1e-10,
                "--output", out)
    assert run.returncode == 0, run.stderr
    rows = list(csv.reader(out.open()))
    assert rows[0] == ["time", "x", "v"]
    assert len(rows) == 12
    assert float(rows[1][0]) == 0.0 and float(rows[-1][0]) == 1.0
    assert len(rows[5][1].replace("-", "").replace(".", "").split("e")[0]) >= 16   # 17 significant digits
    t = np.array([float(r[0]) for r in rows[1:]])
    x = np.array([float(r[1]) for r in rows[1:]])
    assert np.max(np.abs(x - np.cos(2.0 * t))) < 1e-8


def test_parameter_override_and_saveat_and_vars(oscillator, tmp_path):
    out = tmp_path / "osc.csv"
    run = dyadc("simulate", oscillator, "--stop", 1.0, "--saveat", 0.25, "-p", "k=9", "--vars", "x",
                "--rtol", 1e-10, "--atol", 1e-10, "--output", out)
    assert run.returncode == 0, run.stderr
    rows = list(csv.reader(out.open()))
    assert rows[0] == ["time", "x"]
    assert [float(r[0]) for r in rows[1:]] == [0.0, 0.25, 0.5, 0.75, 1.0]
    assert abs(float(rows[-1][1]) - math.cos(3.0)) < 1e-8


def test_source_error_is_located_without_traceback(tmp_path):
    bad = tmp_path / "Bad.dyad"
    bad.write_text("component Bad\n  variable x::Real\nrelations\n  der(x) = y +\nend\n")
    run = dyadc("simulate", bad, "--stop", 1)
    assert run.returncode == 1
    assert run.stderr.startswith(f"{bad}:5:1: error:")
    assert "Traceback" not in run.stderr


def test_unknown_parameter_is_an_error_with_a_suggestion(oscillator):
    run = dyadc("simulate", oscillator, "--stop", 1, "-p", "kk=2")
    assert run.returncode == 1
    assert "unknown parameter 'kk'" in run.stderr and "'k'" in run.stderr
    assert "Traceback" not in run.stderr


def test_bad_override_syntax(oscillator):
    run = dyadc("simulate", oscillator, "--stop", 1, "-p", "k")
    assert run.returncode == 1 and "NAME=VALUE" in run.stderr


def test_unknown_model_name():
    run = dyadc("simulate", "No.Such.Model", "--stop", 1)
    assert run.returncode == 1 and "error:" in run.stderr and "Traceback" not in run.stderr


def test_solver_failure_reports_time_and_leaves_no_file(tmp_path):
    model = tmp_path / "Doomed.dyad"
    model.write_text(DOOMED)
    out = tmp_path / "doomed.csv"
    run = dyadc("simulate", model, "--stop", 2, "--output", out)
    assert run.returncode != 0
    assert "failed at t = " in run.stderr
    reached = float(run.stderr.split("failed at t = ")[1].split(":")[0])
    assert 0.9 < reached <= 1.0 + 1e-6
    assert not out.exists()
    assert list(tmp_path.iterdir()) == [model]


def test_help_explains_the_commands():
    run = dyadc("--help")
    assert run.returncode == 0
    for command in ("simulate", "check", "inspect", "compile", "test", "animate"):
        assert command in run.stdout


def test_inspect_prints_every_pass():
    run = dyadc("inspect", MODELS / "ComponentTests" / "Pendulum.dyad", "--lib", MODELS)
    assert run.returncode == 0, run.stderr
    for part in ("structural index", "states", "dummy derivatives", "BLT blocks", "torn", "pruned"):
        assert part in run.stdout
