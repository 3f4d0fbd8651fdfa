"""`dyadc simulate` options: --saveat lists and ranges, -p values with units, every number checked
(and the output size bounded) before the compiler runs, generated module names with their namespace."""
import csv
import math
import subprocess
import sys
from pathlib import Path

import pytest

import compiler.pipeline
from compiler.cli import main
from compiler.cli.options import parse_saveat
from compiler.lower.generate import module_name

ROOT = Path(__file__).resolve().parents[2]
MODELS = ROOT / "tests" / "models"

# k in N/m, m in kg, L in m (Dyad types); n has no unit; x(t) = L - 0.5 + (1.5 - L) cos(sqrt(k/m) t)
OSCILLATOR = """\
component Oscillator
  parameter k::TranslationalSpringConstant = 4.0
  parameter m::Mass = 1.0
  parameter L::Length = 0.5
  parameter n::Real = 1.0
  variable x::Position(initial = 1.0)
  variable v::Velocity(initial = 0.0)
relations
  der(x) = v
  m * der(v) = -k * (x - L + 0.5) * n
end
"""


@pytest.fixture
def oscillator(tmp_path):
    path = tmp_path / "Oscillator.dyad"
    path.write_text(OSCILLATOR)
    return path


@pytest.fixture
def no_compile(monkeypatch):
    """Fails the test if the compiler runs: checks must refuse before any work."""
    def refuse(*args, **kwargs):
        raise AssertionError("the compiler ran although an option was invalid")
    monkeypatch.setattr(compiler.pipeline, "compile_spec", refuse)


def rows_of(path):
    rows = list(csv.reader(Path(path).open()))
    return rows[0], [[float(x) for x in row] for row in rows[1:]]


def simulate(model, *args):
    return main(["simulate", str(model), "--rtol", "1e-10", "--atol", "1e-10", *map(str, args)])


# ------------------------------------------------------------------------------------------ --saveat

def test_saveat_takes_a_list_of_times(oscillator, tmp_path):
    out = tmp_path / "list.csv"
    assert simulate(oscillator, "--stop", 2, "--saveat", "0,0.5,1.25", "--output", out) == 0
    header, rows = rows_of(out)
    assert [r[0] for r in rows] == [0.0, 0.5, 1.25]
    assert rows[2][1] == pytest.approx(math.cos(2 * 1.25), abs=1e-8)


def test_saveat_takes_a_first_step_last_range(oscillator, tmp_path):
    out = tmp_path / "range.csv"
    assert simulate(oscillator, "--stop", 1, "--saveat", "0.2:0.1:0.6", "--output", out) == 0
    _, rows = rows_of(out)
    # the start is always on the grid (the initial state); the range ends exactly at its last point
    assert [r[0] for r in rows] == pytest.approx([0.0, 0.2, 0.3, 0.4, 0.5, 0.6], abs=1e-15)
    assert rows[-1][0] == 0.6


def test_saveat_interval_includes_the_stop_time():
    assert list(parse_saveat("0.3", 0.0, 1.0).grid()) == pytest.approx([0.0, 0.3, 0.6, 0.9, 1.0])
    assert list(parse_saveat("0.25", 0.0, 1.0).grid()) == [0.0, 0.25, 0.5, 0.75, 1.0]
    assert parse_saveat("0.25", 0.0, 1.0).count() == 5
    assert parse_saveat("0:0.1:0.3", 0.0, 1.0).count() == len(parse_saveat("0:0.1:0.3", 0.0, 1.0).grid()) == 4


@pytest.mark.parametrize("saveat, words", [
    ("0,0.5,3", "time 3 lies outside the simulated span [0, 2]"),
    ("-1,0.5", "time -1 lies outside"),
    ("0:0.1:5", "time 5 lies outside"),
    ("0,nan", "not a finite time"),
    ("0:inf:1", "not a finite time"),
    ("0:0:1", "the step must be positive"),
    ("1:0.1:0.5", "ends (0.5) before it begins (1)"),
    ("0:1", "is not a range"),
    ("0,x", "`x` is not a number"),
    ("-0.5", "interval must be positive"),
])
def test_bad_saveat_is_refused_before_compiling(oscillator, no_compile, capsys, saveat, words):
    assert simulate(oscillator, "--stop", 2, f"--saveat={saveat}") == 1
    err = capsys.readouterr().err
    assert err.startswith("error: --saveat") and words in err and "Traceback" not in err


# --------------------------------------------------------------------------------------- -p units

def test_parameter_values_with_units_convert_to_the_declared_unit(oscillator, tmp_path):
    plain, with_units = tmp_path / "plain.csv", tmp_path / "units.csv"
    assert simulate(oscillator, "--stop", 1, "-p", "k=9", "-p", "m=1", "-p", "L=0.1", "--output", plain) == 0
    assert simulate(oscillator, "--stop", 1, "-p", "k=0.009kN/m", "-p", "m=1000g", "-p", "L=100mm",
                    "--output", with_units) == 0
    assert plain.read_bytes() == with_units.read_bytes()
    _, rows = rows_of(plain)
    assert rows[-1][1] == pytest.approx(-0.4 + 1.4 * math.cos(3.0), abs=1e-8)


def test_unit_forms_users_type(oscillator, tmp_path):
    reference = tmp_path / "reference.csv"
    assert simulate(oscillator, "--stop", 0.5, "-p", "k=100000", "--output", reference) == 0
    for value in ("1e5N/m", "1e5 N/m", "100kN/m", "0.1 MN/m", "1e2N/mm"):
        out = tmp_path / "k.csv"
        assert simulate(oscillator, "--stop", 0.5, "-p", f"k={value}", "--output", out) == 0, value
        assert out.read_bytes() == reference.read_bytes(), value


def test_units_on_a_library_model_parameter(tmp_path):
    """Pendulum's link mass is a Dyad `Mass` (kg): 1500 g is 1.5 kg, bit for bit."""
    outputs = []
    for value in ("1.5", "1500g"):
        out = tmp_path / f"pendulum_{len(outputs)}.csv"
        assert main(["simulate", "ComponentTests.Pendulum", "--lib", str(MODELS), "--stop", "0.5",
                     "--points", "11", "-p", f"link.m={value}", "--vars", "joint.phi", "--output",
                     str(out)]) == 0
        outputs.append(out.read_bytes())
    assert outputs[0] == outputs[1]


@pytest.mark.parametrize("override, words", [
    ("m=2m", ["parameter 'm'", "`kg`", "`m`", "does not convert"]),
    ("L=3s", ["parameter 'L'", "`m`", "`s`", "does not convert"]),
    ("k=5N", ["parameter 'k'", "`N/m`", "`N`"]),
    ("n=2m", ["parameter 'n' declares no unit", "plain number"]),
])
def test_inconsistent_units_are_refused_naming_parameter_and_both_units(oscillator, capsys, override, words):
    assert simulate(oscillator, "--stop", 1, "-p", override) == 1
    err = capsys.readouterr().err
    assert err.startswith("error:") and "Traceback" not in err
    for word in words:
        assert word in err, (word, err)


@pytest.mark.parametrize("override, words", [
    ("m=2furlong", "-p m=2furlong: unknown unit `furlong`"),
    ("L=3m/", "ends where a unit symbol is expected"),
    ("T=20degC+", "unexpected `+`"),
])
def test_unreadable_units_are_refused_before_compiling(oscillator, no_compile, capsys, override, words):
    assert simulate(oscillator, "--stop", 1, "-p", override) == 1
    err = capsys.readouterr().err
    assert err.startswith("error:") and words in err, err


@pytest.mark.parametrize("value", ["nan", "inf", "-inf", "1e400"])
def test_non_finite_parameter_values_are_refused_before_compiling(oscillator, no_compile, capsys, value):
    assert simulate(oscillator, "--stop", 1, "-p", f"k={value}") == 1
    err = capsys.readouterr().err
    assert err.startswith("error: parameter override `k=") and "finite" in err


# -------------------------------------------------------------------------------- numeric options

@pytest.mark.parametrize("args, words", [
    (["--rtol", "0"], "--rtol must be positive, got 0"),
    (["--rtol=-1e-6"], "--rtol must be positive"),
    (["--rtol", "inf"], "--rtol must be a finite number"),
    (["--atol", "nan"], "--atol must be a finite number"),
    (["--atol", "0"], "--atol must be positive"),
    (["--stop", "inf"], "--stop must be a finite number"),
    (["--stop", "nan"], "--stop must be a finite number"),
    (["--start=-inf"], "--start must be a finite number"),
    (["--start", "2"], "--stop 1 must be after --start 2"),
    (["--start", "1"], "--stop 1 must be after --start 1"),
    (["--points", "1"], "--points must be at least 2"),
    (["--points", "100000000"], "100,000,000 output values"),
    (["--saveat", "1e-9"], "1,000,000,001 output values"),
    (["--points", "1000", "--max-output-values", "999"], "limit of 999"),
    (["--max-output-values", "0"], "--max-output-values must be at least 1"),
])
def test_numeric_options_are_refused_before_compiling(oscillator, no_compile, capsys, args, words):
    argv = ["simulate", str(oscillator), "--stop", "1", *args]
    assert main(argv) == 1
    err = capsys.readouterr().err
    assert err.startswith("error:") and words in err and "Traceback" not in err, err


def test_output_limit_counts_every_signal_once_the_model_is_known(oscillator, capsys):
    # 400 times x (time, x, v) = 1200 values
    assert simulate(oscillator, "--stop", 1, "--points", 400, "--max-output-values", 1199) == 1
    err = capsys.readouterr().err
    assert "would store 1,200 output values (400 times x 3 columns)" in err and "limit of 1,199" in err
    assert simulate(oscillator, "--stop", 1, "--points", 400, "--max-output-values", 1200) == 0


def test_output_limit_from_the_environment(oscillator, no_compile, capsys, monkeypatch):
    monkeypatch.setenv("DYADC_MAX_OUTPUT_VALUES", "50")
    assert simulate(oscillator, "--stop", 1, "--points", 51) == 1
    assert "limit of 50" in capsys.readouterr().err
    monkeypatch.setenv("DYADC_MAX_OUTPUT_VALUES", "lots")
    assert simulate(oscillator, "--stop", 1) == 1
    assert "$DYADC_MAX_OUTPUT_VALUES must be a positive integer" in capsys.readouterr().err


def test_nan_tolerance_is_an_error_not_an_endless_loop(oscillator):
    """In a fresh process with a timeout: before the check, IDAS looped at 100% CPU forever."""
    for option in ("--rtol", "--atol"):
        run = subprocess.run([sys.executable, "-m", "compiler", "simulate", str(oscillator), "--stop", "1",
                              option, "nan"], capture_output=True, text=True, cwd=ROOT, timeout=120)
        assert run.returncode == 1
        assert run.stderr.startswith(f"error: {option} must be a finite number, got nan")


# ------------------------------------------------------------------------------ generated modules

def test_module_names_keep_the_namespace():
    assert module_name("MultibodyComponents.PlanarMechanics.examples.excavator.Excavator") == \
        "multibody_components__planar_mechanics__examples__excavator__excavator"
    assert module_name("PkgA.Excavator") != module_name("PkgB.Excavator")
    assert module_name("Oscillator") == "oscillator"
    assert module_name("my-lib.Model") == "my_lib__model"
    assert module_name("class") == "_class"


def test_two_models_of_one_name_in_different_packages_get_two_modules(tmp_path, capsys):
    library = tmp_path / "lib"
    for package in ("PkgA", "PkgB"):
        (library / package).mkdir(parents=True)
        (library / package / "Oscillator.dyad").write_text(OSCILLATOR)
    out = tmp_path / "generated"
    for package in ("PkgA", "PkgB"):
        assert main(["compile", f"{package}.Oscillator", "--lib", str(library), "-o", str(out)]) == 0
    assert main(["compile", "PkgA.Oscillator", "--lib", str(library), "-o", str(out), "--name", "mine"]) == 0
    assert sorted(p.name for p in out.glob("*.py")) == ["mine.py", "pkg_a__oscillator.py", "pkg_b__oscillator.py"]
