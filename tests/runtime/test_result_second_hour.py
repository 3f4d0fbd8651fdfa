"""Issue 28, results where people want them: Result.to_pandas, Result.plot() for a notebook, the
run's parameters in the Result and in every output format, events with their direction."""
from __future__ import annotations

import json
import math
import textwrap

import numpy as np
import pytest

from compiler import api

MODEL = """
component Swing
  parameter w::Real = 1
  parameter a::Real = 2 * w
  variable x::Real(units = "m")
  variable y::Real
relations
  initial x = 0
  initial y = 0
  der(x) = a * cos(w * time)
  der(y) = if x > 1 then 1 else 0
end
"""


@pytest.fixture(scope="module")
def swing(tmp_path_factory):
    """x = (a / w) sin(w t) with w = 2, a = 4 (bound to w): x crosses 1 upward at t = pi/12 and
    downward at t = 5 pi/12."""
    path = tmp_path_factory.mktemp("swing") / "Swing.dyad"
    path.write_text(textwrap.dedent(MODEL), encoding="utf-8")
    return api.simulate(str(path), 2.0, points=21, params={"w": 2.0}, rtol=1e-10, atol=1e-10)


def test_the_results_parameters_are_the_values_of_the_run(swing):
    assert swing.parameters == {"w": 2.0, "a": 4.0}


def test_events_carry_their_direction(swing):
    assert [(e["event"], e["direction"]) for e in swing.events] == [("x > 1", "rising"),
                                                                      ("x > 1", "falling")]
    assert [e["time"] for e in swing.events] == pytest.approx([math.pi / 12, 5 * math.pi / 12], abs=1e-8)


def test_write_events_is_a_csv_of_time_event_direction(swing, tmp_path):
    swing.write_events(tmp_path / "events.csv")
    lines = (tmp_path / "events.csv").read_text().splitlines()
    assert lines[0] == "time,event,direction"
    assert [line.split(",")[1:] for line in lines[1:]] == [["x > 1", "rising"], ["x > 1", "falling"]]
    assert float(lines[1].split(",")[0]) == swing.events[0]["time"]


def test_to_pandas_is_indexed_by_time_with_the_units(swing):
    frame = swing.to_pandas()
    assert frame.index.name == "time" and np.array_equal(frame.index.to_numpy(), swing.time)
    assert list(frame.columns) == swing.names
    assert np.array_equal(frame["x"].to_numpy(), swing["x"])
    assert frame.attrs["units"] == {"x": "m"}
    assert frame.attrs["parameters"] == {"w": 2.0, "a": 4.0}
    assert list(swing.to_pandas(["y"]).columns) == ["y"]


def test_plot_without_a_file_returns_the_figure(swing, tmp_path, monkeypatch):
    from matplotlib.figure import Figure
    monkeypatch.chdir(tmp_path)
    figure = swing.plot()
    assert isinstance(figure, Figure) and len(figure.axes) == 2      # m and no unit
    assert list(tmp_path.iterdir()) == []


def test_every_format_carries_the_parameters(swing, tmp_path):
    written = swing.write(tmp_path / "run.csv")
    assert written == [str(tmp_path / "run.csv"), str(tmp_path / "run.csv.json")]
    assert (tmp_path / "run.csv").read_text().splitlines()[0] == "time,x,y"        # a plain table
    sidecar = json.loads((tmp_path / "run.csv.json").read_text())
    assert sidecar == {"model": "Swing", "units": {"x": "m"}, "parameters": {"w": 2.0, "a": 4.0}}

    import pyarrow.parquet as pq
    swing.write(tmp_path / "run.parquet")
    schema = pq.read_schema(tmp_path / "run.parquet")
    assert json.loads(schema.metadata[b"parameters"]) == {"w": 2.0, "a": 4.0}

    from scipy.io import loadmat
    swing.write(tmp_path / "run.mat")
    mat = loadmat(tmp_path / "run.mat")
    assert [str(n[0][0]) for n in mat["parameter_names"]] == ["w", "a"]
    assert mat["parameter_values"][:, 0].tolist() == [2.0, 4.0]

    swing.write(tmp_path / "run.npz")
    with np.load(tmp_path / "run.npz") as npz:
        assert npz["__parameter_names__"].tolist() == ["w", "a"]
        assert npz["__parameter_values__"].tolist() == [2.0, 4.0]
