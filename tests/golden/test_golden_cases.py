"""Golden-trajectory tests: every metadata test case against its golden, and the machinery itself
(corruption is caught and located, goldens are written only on an explicit --accept)."""
from __future__ import annotations

import functools
import shutil
import os
from pathlib import Path

import numpy as np
import pytest

from compiler import api

from compiler.testing import golden
from compiler.errors import DyadError
from compiler.syntax import ast
from compiler.syntax.parser import parse_source
from compiler.testing.golden_cases import cases_from_metadata, discover
from compiler.testing.golden_compare import Golden, compare_signals, golden_path, read_golden, write_golden

HERE = Path(__file__).resolve().parent
DECAY = str(HERE / "models" / "Decay.dyad")
EXCAVATOR = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"


@functools.lru_cache(maxsize=None)
def _compiled(model: str):
    return api.compile(model)


# ------------------------------------------------------------------ every case of the library

@pytest.mark.parametrize("case", discover(use_env=False), ids=lambda c: c.label)
def test_metadata_case_matches_its_golden(case, each_codegen):
    report = golden.run_case(_compiled(case.model), case, HERE)
    assert report.passed, report.format()


def test_discovery_finds_the_excavator_dig_cycle_and_lib_dir_cases():
    labels = {c.label for c in discover()}
    assert f"{EXCAVATOR}.dig_cycle" in labels
    with_lib = {c.label for c in discover([str(HERE / "models")])}
    assert "Decay.decay" in with_lib and f"{EXCAVATOR}.dig_cycle" in with_lib


def test_excavator_case_reads_the_metadata():
    (case,) = [c for c in discover() if c.model == EXCAVATOR]
    assert case.name == "dig_cycle" and case.stop == 12 and case.points == 1201
    assert case.rtol == 1e-6 and len(case.signals) == 64
    assert case.tube("soil.F_x")[0] == case.atol["soil.F_x"] > 0


# --------------------------------------------------------------------- the machinery (Decay)

@pytest.fixture
def decay(tmp_path):
    """The Decay model's case, its compilation, and an empty golden directory."""
    compilation = _compiled(DECAY)
    (case,) = golden.cases_of_compilation("Decay", compilation)
    return case, compilation, tmp_path


def test_running_without_accept_never_writes_a_golden(decay):
    case, compilation, directory = decay
    report = golden.run_case(compilation, case, directory)
    assert not report.passed
    assert "no golden file" in report.error and f"--golden {directory} --accept" in report.error
    assert os.listdir(directory) == []


def test_update_writes_the_listed_signals_and_the_run_then_passes(decay):
    case, compilation, directory = decay
    assert golden.accept_case(compilation, case, directory).passed
    stored = read_golden(golden_path(directory, case))
    assert list(stored.columns) == ["x", "y"]
    np.testing.assert_allclose(stored.time, np.linspace(0, 1, 11), rtol=0, atol=1e-15)
    np.testing.assert_allclose(stored.columns["x"], np.exp(-2 * stored.time), rtol=1e-8)
    report = golden.run_case(compilation, case, directory)
    assert report.passed, report.format()
    assert all(c.ratio < 0.5 for c in report.signals)


def test_a_corrupted_golden_is_caught_naming_signal_time_and_values(decay):
    case, compilation, directory = decay
    golden.accept_case(compilation, case, directory)
    path = golden_path(directory, case)
    stored = read_golden(path)
    row = 5                                          # t = 0.5
    atol, rtol = case.tube("y")
    stored.columns["y"][row] += 10 * (atol + rtol * abs(stored.columns["y"][row]))
    write_golden(path, stored.time, stored.columns)
    before = Path(path).read_bytes()

    report = golden.run_case(compilation, case, directory)
    assert not report.passed
    (failure,) = report.failures()
    assert "signal y" in failure and "t = 0.5" in failure
    assert f"{stored.columns['y'][row]:.10g}" in failure          # the golden value it expected
    assert [c.name for c in report.signals if not c.passed] == ["y"]
    assert Path(path).read_bytes() == before                      # a failing run does not rewrite

    assert golden.accept_case(compilation, case, directory).passed   # only --accept repairs it
    assert golden.run_case(compilation, case, directory).passed


def test_update_refuses_to_write_when_the_final_value_disagrees(decay):
    case, compilation, directory = decay
    wrong = type(case)(**{**case.__dict__, "final": {"x": 0.2}})
    report = golden.accept_case(compilation, wrong, directory)
    assert not report.passed and "NOT written" in report.format()
    assert os.listdir(directory) == []


def test_dyadc_test_exit_status_and_explicit_accept(decay, capsys):
    from compiler.cli import main
    _, _, directory = decay
    assert main(["test", DECAY, "--golden", str(directory)]) == 1
    assert os.listdir(directory) == []
    assert main(["test", DECAY, "--golden", str(directory), "--accept"]) == 0
    assert os.listdir(directory) == ["Decay.decay.csv"]
    assert main(["test", DECAY, "--golden", str(directory)]) == 0
    out = capsys.readouterr().out
    assert "1 passed, 0 failed" in out and "1 accepted, 0 failed" in out


def test_a_model_without_cases_is_an_error(tmp_path, capsys):
    model = tmp_path / "Plain.dyad"
    model.write_text("component Plain\n  variable x::Real\nrelations\n  initial x = 1\n  der(x) = -x\nend\n")
    from compiler.cli import main
    assert main(["test", str(model), "--golden", str(tmp_path)]) == 1
    assert "declares no test cases" in capsys.readouterr().err


# ------------------------------------------------------------------- comparison and parsing

def _case(**spec):
    base = {"stop": 1, "atol": {"a": 0.1}, "expect": {"signals": ["a"]}}
    base.update(spec)
    (case,) = cases_from_metadata("M", {"tests": {"c": base}}, None)
    return case


def test_golden_on_another_grid_is_interpolated():
    case = _case()
    stored = Golden(np.linspace(0, 1, 11), {"a": np.linspace(0, 1, 11) ** 2}, "g.csv")
    t = np.linspace(0, 1, 7)
    checks, notes = compare_signals(case, t, {"a": t ** 2}, stored)
    assert checks[0].passed and checks[0].ratio < 0.1       # linear-interpolation error only
    assert "interpolated" in notes[0]
    checks, _ = compare_signals(case, t, {"a": t ** 2 + 0.2 * (t > 0.6)}, stored)
    assert not checks[0].passed and checks[0].time > 0.6


def test_relative_tube_and_nan_are_judged():
    case = _case(atol={"a": 0.0}, signal_rtol={"*": 1e-3})
    stored = Golden(np.array([0.0, 1.0]), {"a": np.array([1000.0, 2000.0])}, "g.csv")
    assert compare_signals(case, stored.time, {"a": np.array([1000.5, 2001.5])}, stored)[0][0].passed
    assert not compare_signals(case, stored.time, {"a": np.array([1000.5, 2002.5])}, stored)[0][0].passed
    assert not compare_signals(case, stored.time, {"a": np.array([np.nan, 2000.0])}, stored)[0][0].passed


def test_missing_golden_column_names_the_signal():
    case = _case()
    stored = Golden(np.array([0.0, 1.0]), {"b": np.zeros(2)}, "g.csv")
    (check,), _ = compare_signals(case, stored.time, {"a": np.zeros(2)}, stored)
    assert not check.passed and "no column `a`" in check.message("M.c")


@pytest.mark.parametrize("spec, words", [
    ({"atol": {"a": "abc"}}, '"atol" of `a` must be a finite number'),
    ({"stop": "twelve"}, '"stop" must be a finite number'),
    ({"rtol": 0}, "must be positive"),
    ({"atol": {"a": 1, "zz": 1}}, "does not compare: zz"),
])
def test_malformed_cases_are_located_errors(spec, words):
    with pytest.raises(DyadError) as caught:
        _case(**spec)
    assert words in caught.value.message


def test_case_errors_point_at_the_case_key_in_the_source():
    text = Path(DECAY).read_text()
    broken = text.replace('"atol": {"x": 1e-6, "y": 3e-6}', '"atol": {"x": 1e-6, "y": "?"}')
    assert broken != text
    (definition,) = parse_source(broken, DECAY).definitions
    with pytest.raises(DyadError) as caught:
        cases_from_metadata("Decay", ast.metadata_dict(definition.metadata)["Dyad"], definition.span)
    span = caught.value.span
    # the key's place is looked up in the file on disk, whose layout the edit above keeps
    assert (span.file, span.line, span.column) == (DECAY, 16, 7) and "`y`" in caught.value.message


def test_golden_files_are_written_atomically_with_17_digits(tmp_path):
    path = str(tmp_path / "g.csv")
    write_golden(path, np.array([0.0, 0.1]), {"a": np.array([1 / 3, 2 / 3])})
    assert Path(path).read_text().splitlines()[1] == "0,0.33333333333333331"
    assert [p.name for p in tmp_path.iterdir()] == ["g.csv"]       # no temporary left behind


def test_discovery_mode_reports_a_model_that_does_not_compile_and_runs_the_rest(tmp_path, monkeypatch):
    library = tmp_path / "lib"
    library.mkdir()
    shutil.copy(DECAY, library / "Decay.dyad")
    (library / "Broken.dyad").write_text(
        'component Broken\n  part = NoSuchThing()\nrelations\n'
        'metadata {"Dyad": {"tests": {"c": {"stop": 1, "atol": 1, "expect": {"signals": ["x"]}}}}}\nend\n')
    only_this_library = [c for c in discover([str(library)]) if c.model in ("Broken", "Decay")]
    monkeypatch.setattr(golden, "discover", lambda lib_dirs, **scope: only_this_library)
    reports = golden.run_tests(None, [str(library)], accept=True, golden_dir=tmp_path)
    by_model = {r.case.model: r for r in reports}
    assert not by_model["Broken"].passed and "Broken.dyad:2:3" in by_model["Broken"].error
    assert by_model["Decay"].passed and (tmp_path / "Decay.decay.csv").is_file()


def test_a_nominal_for_an_unknown_that_does_not_exist_is_a_located_error(decay):
    case, compilation, directory = decay
    wrong = type(case)(**{**case.__dict__, "nominal": {"zz": 2.0}})
    report = golden.accept_case(compilation, wrong, directory)
    assert not report.passed and "nominal given for `zz`" in report.error
    assert "Decay.dyad:16:7" in report.error


def test_cli_golden_folder_and_explicit_accept(tmp_path, capsys):
    from compiler.cli import main
    folder = tmp_path / "my_goldens"
    assert main(["test", DECAY, "--golden", str(folder)]) == 1
    assert not folder.exists()                                   # a missing golden is not created
    assert f"--golden {folder} --accept" in capsys.readouterr().out
    assert main(["test", DECAY, "--golden", str(folder), "--accept"]) == 0
    assert os.listdir(folder) == ["Decay.decay.csv"]
    assert main(["test", DECAY, "--golden", str(folder)]) == 0
    assert main(["test", DECAY, "--golden", str(folder), "--update"]) == 0   # the old spelling


def test_without_a_model_only_the_named_libraries_cases_run(tmp_path, monkeypatch):
    monkeypatch.delenv("DYADC_PATH", raising=False)
    library = tmp_path / "lib"
    library.mkdir()
    shutil.copy(DECAY, library / "Decay.dyad")
    reports = golden.run_tests(None, [str(library)], golden_dir=tmp_path / "goldens", accept=True)
    assert [r.case.label for r in reports] == ["Decay.decay"]      # not the shipped excavator
    assert all(r.passed for r in reports)
