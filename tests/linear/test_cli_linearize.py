"""`dyadc linearize`: the options of issue 29, its outputs and its errors."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from compiler.cli import main

MODELS = str(Path(__file__).resolve().parent.parent / "models")


def linearize(*arguments: str) -> int:
    return main(["linearize", *arguments, "-L", MODELS])


def test_json_output_and_summary(tmp_path, capsys):
    output = tmp_path / "rc.json"
    assert linearize("Linear.RCLowPass", "--outputs", "vout", "-p", "R=2kOhm", "--output", str(output)) == 0
    data = json.loads(output.read_text())
    assert data["A"] == [[-0.5]] and data["B"] == [[0.5]] and data["C"] == [[1.0]] and data["D"] == [[0.0]]
    assert data["operating_point"]["parameters"]["R"] == 2000.0
    text = capsys.readouterr().out
    assert "poles:\n  -0.5\n" in text and "vout / V = (0.5) / (1 s + 0.5)" in text


def test_sensitivity_and_comp_sensitivity_add_to_one(tmp_path):
    files = {kind: tmp_path / f"{kind}.npz" for kind in ("sensitivity", "comp-sensitivity")}
    for kind, path in files.items():
        assert linearize("Linear.DCMotorPI", f"--{kind}", "y", "--output", str(path)) == 0
    s, t = (np.load(path) for path in files.values())
    assert np.abs(s["C"] + t["C"]).max() < 1e-12 and np.abs(s["D"] + t["D"] - 1.0).max() < 1e-12
    assert np.array_equal(s["A"], t["A"]) and list(s["inputs"]) == ["y"]


def test_loop_transfer_as_mat(tmp_path):
    import scipy.io
    path = tmp_path / "L.mat"
    assert linearize("Linear.DCMotorPI", "--loop-transfer", "u", "--minimal", "--output", str(path)) == 0
    data = scipy.io.loadmat(path)
    assert data["A"].shape == (3, 3)          # integrator and motor: already minimal
    assert [str(x[0]) for x in data["outputs"].ravel()] == ["u"]


def test_opened_loop_at_a_time(capsys):
    assert linearize("Linear.DCMotorPI", "--inputs", "u", "--outputs", "y", "--open", "u", "--at", "0.5") == 0
    assert "linear model at t = 0.5: 3 states, 1 inputs, 1 outputs" in capsys.readouterr().out


@pytest.mark.parametrize("arguments, message", [
    (["--inputs", "uu"], "`uu` is not a free top-level input or an analysis point of `Linear.DCMotorPI`; did you mean `u`?"),
    (["--open", "r"], "`r` is not an analysis point of `Linear.DCMotorPI`"),
    (["--outputs", "motor.ww"], "unknown output 'motor.ww' in model Linear.DCMotorPI"),
    (["--op", "controller.Kp=3"], "--op controller.Kp=...: `controller.Kp` is not an input of this linearization"),
    (["--sensitivity", "u", "--inputs", "r"], "--sensitivity gives its own input and output"),
    (["--output", "m.csv"], "--output m.csv: a linear model is written as .json, .mat, .npz"),
    (["--plot", "m.svg"], "--plot m.svg: the plot is written as .png"),
])
def test_errors(arguments, message, capsys):
    assert linearize("Linear.DCMotorPI", *arguments) == 1
    assert message in capsys.readouterr().err


def test_free_inputs_still_refused_by_simulate(capsys):
    assert main(["simulate", "Linear.RCLowPass", "--stop", "1", "-L", MODELS]) == 1
    assert "its connector V is left open" in capsys.readouterr().err


def test_bode_plot(tmp_path):
    path = tmp_path / "bode.png"
    assert linearize("Linear.MassSpringDamper", "--outputs", "mass.s", "mass.v", "--plot", str(path)) == 0
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 20_000


def test_an_input_whose_derivative_is_needed_is_refused_where_it_is_differentiated(capsys):
    assert linearize("Linear.PositionDriven") == 1
    err = capsys.readouterr().err
    assert "PositionDriven.dyad:8:3: error: input `u` of `Linear.PositionDriven` would need its time " \
           "derivative (`x` follows it and is differentiated)" in err
