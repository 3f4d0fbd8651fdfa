"""`dyadc run File.dyad:Analysis` for Dyad's linear analyses (tests/models/Linear/analyses.dyad),
checked against the DC motor's closed forms (tests/linear/test_closed_forms.py)."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

from compiler.cli import main
from tests.linear.test_closed_forms import CHARACTERISTIC, controller, plant

MODELS = Path(__file__).resolve().parent.parent / "models"
ANALYSES = MODELS / "Linear" / "analyses.dyad"


def peak(response) -> float:
    """max over w of |response(w)|, by scipy's bounded search near the largest of a fine grid."""
    omega = np.logspace(-1, 3, 20001)
    k = int(np.argmax(np.abs(response(omega))))
    found = minimize_scalar(lambda w: -abs(response(w)), bounds=(omega[k - 1], omega[k + 1]),
                            method="bounded", options={"xatol": 1e-12})
    return -found.fun


def run(tmp_path, name: str, *extra: str) -> dict:
    output = tmp_path / f"{name}.json"
    assert main(["run", f"{ANALYSES}:{name}", "-L", str(MODELS), "--output", str(output), *extra]) == 0
    return json.loads(output.read_text())


def test_linear_analysis_poles_and_plots(tmp_path, capsys):
    data = run(tmp_path, "MotorLinear")
    poles = [complex(*p) for p in data["results"]["poles"]]
    assert np.sort_complex(poles) == pytest.approx(np.sort_complex(np.roots(CHARACTERISTIC)), rel=1e-12)
    assert data["settings"] == {"inputs": ["r"], "outputs": ["y"], "loop_openings": [], "duration": 3.0}
    assert [Path(f).name for f in data["plots"]] == ["MotorLinear_bode.png", "MotorLinear_step.png"]
    assert all(Path(f).stat().st_size > 10_000 for f in data["plots"])
    assert "0.4482" in capsys.readouterr().out          # damping of the complex pair


def test_closed_loop_analysis_phase_margin_and_peak_sensitivity(tmp_path):
    data = run(tmp_path, "MotorLoop", "-p", "gain=4")
    KP = 4.0     # the analysis parameter `gain` sets controller.Kp
    loop = lambda w: (KP + 50.0 / (1j * w)) * plant(1j * w)  # noqa: E731
    crossover = brentq(lambda w: abs(loop(w)) - 1.0, 0.1, 1000.0, xtol=1e-14)
    phase_margin = 180.0 + np.degrees(np.angle(loop(crossover)))
    results = data["results"]
    assert results["gain_crossover"] == pytest.approx(crossover, rel=1e-6)
    assert results["phase_margin_deg"] == pytest.approx(phase_margin, rel=1e-6)
    assert results["Ms"] == pytest.approx(peak(lambda w: 1 / (1 + loop(w))), rel=1e-9)
    grid = np.logspace(-1, 3, 3000)          # wl = 0.1, wu = 1000, num_frequencies default 3000
    balanced = np.abs(1 / (1 + loop(grid)) - loop(grid) / (1 + loop(grid))) / 2
    assert results["disk_margin"] == pytest.approx(1 / balanced.max(), rel=1e-9)
    assert [Path(f).name for f in data["plots"]] == ["MotorLoop_nyquist.png", "MotorLoop_bode.png",
                                                     "MotorLoop_gangoffour.png", "MotorLoop_step.png"]


def test_sensitivity_analysis_at_both_points(tmp_path):
    data = run(tmp_path, "MotorSensitivity")
    expected = peak(lambda w: 1 / (1 + controller(1j * w) * plant(1j * w)))
    for point in ("u", "y"):
        found = data["results"][point]
        assert found["Ms"] == pytest.approx(expected, rel=1e-9)
        assert found["gain_margin_at_least"] == pytest.approx(expected / (expected - 1), rel=1e-9)
    assert sorted(data["systems"]) == ["u", "y"]


def test_a_misspelled_field_is_located(tmp_path, capsys):
    source = tmp_path / "bad.dyad"
    source.write_text('analysis Bad\n  extends ClosedLoopAnalysis(measurement = "y", control_input = "u", '
                      'num_frequency = 10)\n  model = Linear.DCMotorPI()\nend\n')
    assert main(["run", f"{source}:Bad", "-L", str(MODELS), "--output", str(tmp_path / "b.json")]) != 0
    err = capsys.readouterr().err
    assert f"{source}:2:" in err and "has no field `num_frequency`" in err and "num_frequencies" in err


def test_an_unknown_analysis_point_is_located_at_its_field(tmp_path, capsys):
    source = tmp_path / "bad.dyad"
    source.write_text('analysis Bad\n  extends ClosedLoopSensitivityAnalysis(\n    analysis_points = ["u", "yy"])\n'
                      '  model = Linear.DCMotorPI()\nend\n')
    assert main(["run", f"{source}:Bad", "-L", str(MODELS), "--output", str(tmp_path / "b.json")]) == 1
    err = capsys.readouterr().err
    assert f"{source}:3:" in err
    assert "`yy` in `analysis_points` of analysis `Bad` is not an analysis point of `Linear.DCMotorPI`; " \
           "did you mean `y`?" in err
