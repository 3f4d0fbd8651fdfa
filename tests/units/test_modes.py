"""--units error|warn|off on the command line and in the Python API (issue 26, item 6), and the
findings kept with a cached compilation: a cached run reports them without checking again."""
from __future__ import annotations

import warnings

import pytest

from compiler import api
from compiler.cli import run_command
from compiler.errors import DyadError
from compiler.units import check
from compiler.units.mode import UnitWarning

MIXED = """\
component Mixed
  variable v::Voltage
  variable i::Current
relations
  v = 1 + i
  der(i) = -i / 0.1
end
"""


@pytest.fixture
def model(tmp_path):
    path = tmp_path / "Mixed.dyad"
    path.write_text(MIXED)
    return str(path)


def test_the_default_refuses_the_model_at_the_mixing_term(model, capsys):
    assert run_command(["check", model]) == 1
    assert capsys.readouterr().err.splitlines()[0] == (
        f"{model}:5:11: error: units do not match in this equation: left side V, right side A")


def test_warn_reports_each_finding_once_and_goes_on(model, capsys):
    assert run_command(["check", model, "--units", "warn"]) == 0
    err = capsys.readouterr().err
    assert err.splitlines()[0] == (f"{model}:5:11: warning: units do not match in this equation: "
                                   "left side V, right side A")
    assert err.count("warning:") == 1


def test_off_checks_nothing(model, capsys):
    assert run_command(["check", model, "--units", "off"]) == 0
    assert "units" not in capsys.readouterr().err


def test_a_cached_run_reports_the_kept_findings_without_checking_again(model, capsys, monkeypatch):
    assert run_command(["simulate", model, "--stop", "0.1", "--units", "warn"]) == 0
    assert "warning: units do not match" in capsys.readouterr().err

    def not_again(self):
        raise AssertionError("the unit check ran again for a cached compilation")
    monkeypatch.setattr(check.UnitCheck, "run", not_again)
    assert run_command(["simulate", model, "--stop", "0.1"]) == 1
    assert "error: units do not match in this equation" in capsys.readouterr().err
    assert run_command(["simulate", model, "--stop", "0.1", "--units", "warn"]) == 0
    assert "warning: units do not match" in capsys.readouterr().err


def test_an_entry_compiled_without_the_check_is_compiled_again_with_it(model, capsys):
    assert run_command(["simulate", model, "--stop", "0.1", "--units", "off"]) == 0
    assert run_command(["simulate", model, "--stop", "0.1"]) == 1
    assert "error: units do not match" in capsys.readouterr().err


def test_the_python_api_takes_the_same_modes(model):
    with pytest.raises(DyadError, match="units do not match in this equation"):
        api.flatten(model)
    assert api.flatten(model, units="off").unit_findings is None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        flat = api.flatten(model, units="warn")
        result = api.simulate(model, 0.1, units="warn")
    assert [f.message for f in flat.unit_findings] == [
        "units do not match in this equation: left side V, right side A"]
    assert [w.category for w in caught] == [UnitWarning, UnitWarning]
    assert result["v"].shape == result.time.shape


def test_an_unknown_mode_is_refused():
    with pytest.raises(DyadError, match="--units must be one of error, warn, off"):
        api.flatten("ElectricalComponents.Resistor", units="loud")
