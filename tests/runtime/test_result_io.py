"""Result: CSV round trip (exact), atomic writes, plots, serialization of the compiled model."""
from __future__ import annotations

import csv
import os

import numpy as np
import pytest

from tests.runtime import runtime_systems as systems
from compiler import runtime
from compiler.lower.to_casadi import lower


@pytest.fixture(scope="module")
def rc_result():
    return runtime.simulate(lower(systems.rc_circuit()), 0.3, points=31)


def test_csv_round_trip_is_exact(tmp_path, rc_result):
    path = tmp_path / "out" / "rc.csv"
    rc_result.to_csv(path)
    with open(path, newline="") as f:
        header = next(csv.reader(f))
    assert header == ["time"] + rc_result.names
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    assert np.array_equal(data[:, 0], rc_result.time)
    for k, name in enumerate(rc_result.names, start=1):
        assert np.array_equal(data[:, k], rc_result[name])      # %.17g round-trips doubles


def test_csv_with_chosen_columns(tmp_path, rc_result):
    path = tmp_path / "rc.csv"
    rc_result.to_csv(path, names=["R.i", "C.v"])
    assert path.read_text().splitlines()[0] == "time,R.i,C.v"
    with pytest.raises(runtime.ModelInputError, match="no signal 'C.w'"):
        rc_result.to_csv(tmp_path / "bad.csv", names=["C.w"])
    assert not (tmp_path / "bad.csv").exists()


def test_failed_csv_write_leaves_the_old_file_and_no_temporary(tmp_path, rc_result, monkeypatch):
    path = tmp_path / "rc.csv"
    path.write_text("previous contents\n")
    from compiler.runtime import writers
    original = writers._WRITERS[".csv"]

    def write_half_then_fail(temp, time, data, units, parameters):
        original(temp, time[: len(time) // 2], {k: v[: len(time) // 2] for k, v in data.items()}, units,
                 parameters)
        raise OSError("disk full (simulated)")
    monkeypatch.setitem(writers._WRITERS, ".csv", write_half_then_fail)
    with pytest.raises(OSError, match="disk full"):
        rc_result.to_csv(path)
    assert path.read_text() == "previous contents\n"
    assert os.listdir(tmp_path) == ["rc.csv"]


def test_plot_writes_a_png(tmp_path, rc_result):
    path = tmp_path / "rc.png"
    rc_result.plot(path, names=["C.v"])
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_compiled_model_round_trips_through_to_dict(rc_result):
    model = lower(systems.valve_tank())
    clone = runtime.CompiledModel.from_dict(model.to_dict())
    assert clone.to_dict() == model.to_dict()
    a = runtime.simulate(model, 1.0, params={"Kv": 6.0})
    b = runtime.simulate(clone, 1.0, params={"Kv": 6.0})
    assert np.array_equal(a.values, b.values)


def test_unknown_format_version_is_refused():
    data = lower(systems.rc_circuit()).to_dict()
    data["format_version"] = 999
    with pytest.raises(runtime.ModelInputError, match="format"):
        runtime.CompiledModel.from_dict(data)
