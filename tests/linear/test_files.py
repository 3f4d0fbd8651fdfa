"""A linear model written as .json (the key layout of issue 29), .npz and .mat, and its summary."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import scipy.io

from compiler import api
from compiler.linear.files import summary, write

MODELS = [str(Path(__file__).resolve().parent.parent / "models")]


@pytest.fixture(scope="module")
def motor():
    return api.linearize("Linear.DCMotorPI", outputs=["motor.w"], op={"r": 0.5}, lib_dirs=MODELS,
                         cache=False)


def test_json_layout(motor, tmp_path):
    write(motor, tmp_path / "m.json")
    data = json.loads((tmp_path / "m.json").read_text())
    assert sorted(data) == ["A", "B", "C", "D", "inputs", "operating_point", "outputs", "states"]
    assert np.array(data["A"]) == pytest.approx(motor.A, abs=0) and data["B"] == motor.B.tolist()
    assert data["states"] == ["controller.xi", "motor.w", "motor.i"]
    assert data["inputs"] == ["r"] and data["outputs"] == ["motor.w"]
    point = data["operating_point"]
    assert sorted(point) == ["inputs", "parameters", "states", "time"]
    assert point["time"] == 0.0 and point["inputs"] == {"r": 0.5}
    assert point["parameters"]["controller.Kp"] == 10.0 and "r" not in point["parameters"]
    assert point["states"] == {"controller.xi": 0.0, "motor.w": 0.0, "motor.i": 0.0}


def test_npz_and_mat_hold_the_same(motor, tmp_path):
    write(motor, tmp_path / "m.npz")
    write(motor, tmp_path / "m.mat")
    npz = np.load(tmp_path / "m.npz")
    mat = scipy.io.loadmat(tmp_path / "m.mat")
    for key in "ABCD":
        assert np.array_equal(npz[key], getattr(motor, key))
        assert np.array_equal(mat[key], getattr(motor, key))
    assert list(npz["states"]) == motor.states
    assert [str(s[0]) for s in mat["states"].ravel()] == motor.states


def test_summary_lists_poles_gain_and_transfer_function(motor):
    text = summary(motor)
    assert "poles:\n  -5.26202\n  -4.36899 - 8.71393i\n  -4.36899 + 8.71393i" in text
    assert "  motor.w: 1\n" in text
    assert "motor.w / r = (100 s + 500) / (1 s^3 + 14 s^2 + 141 s + 500)" in text
