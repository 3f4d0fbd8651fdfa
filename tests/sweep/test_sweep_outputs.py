"""Issue 28, sweeps: Parquet columns carry units as `simulate`'s do, a grid is plotted as one line
per grid value with units on the axes, `--vars` takes patterns (`*`, `?`; `[` stays an index)."""
from __future__ import annotations

import textwrap

import numpy as np
import pytest

from compiler.errors import DyadError
from compiler.pipeline import compile_spec
from compiler.sweep import SweepOptions, sweep
from compiler.sweep.plot import summary_figure

TANK = """
component Tank
  parameter k::Real(units = "1/s") = 1
  parameter h0::Real(units = "m") = 1
  variable h::Real(units = "m")
  variable q::Real(units = "m/s")
  variable r::Real[2]
relations
  initial h = h0
  q = -k * h
  der(h) = q
  r[1] = h
  r[2] = 2 * h
end
"""


@pytest.fixture(scope="module")
def tank(tmp_path_factory):
    path = tmp_path_factory.mktemp("tank") / "Tank.dyad"
    path.write_text(textwrap.dedent(TANK), encoding="utf-8")
    return compile_spec(str(path))


def run(compilation, design, **options):
    return sweep(compilation, design, SweepOptions(serial=True, stop=1.0, points=11, **options))


def test_parquet_columns_carry_the_declared_units(tank, tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    result = run(tank, {"k": [1.0, 2.0]}, variables=["h", "q"])
    trajectories, samples = result.write(tmp_path / "s.parquet")
    schema = pq.read_schema(trajectories)
    units = {name: (schema.field(name).metadata or {}).get(b"unit") for name in schema.names}
    assert units == {"sample": None, "k": b"1/s", "time": b"s", "h": b"m", "q": b"m/s"}
    assert pq.read_schema(samples).field("k").metadata == {b"unit": b"1/s"}


def test_a_grid_is_drawn_as_one_labelled_line_per_value_with_units(tank):
    result = run(tank, {"k": [0.5, 1.0, 2.0]}, variables=["h"])
    axes = summary_figure(result, ["h"], []).axes
    assert len(axes) == 1
    lines = axes[0].get_lines()
    assert [line.get_label() for line in lines] == ["k = 0.5 [1/s]", "k = 1 [1/s]", "k = 2 [1/s]"]
    assert np.allclose(lines[2].get_ydata(), np.exp(-2.0 * lines[2].get_xdata()), atol=1e-4)
    assert (axes[0].get_xlabel(), axes[0].get_ylabel()) == ("time [s]", "h [m]")


def test_random_samples_keep_the_fan_chart(tank):
    result = run(tank, _sampled(), variables=["h"])
    labels = [line.get_label() for line in summary_figure(result, ["h"], []).axes[0].get_lines()]
    assert labels[0] == "median"


def _sampled():
    from compiler.sweep.design import parse_assignment, sampled_design
    return sampled_design([parse_assignment("k=0.5:2")], 5, "lhs", 1)


def test_vars_takes_patterns_and_keeps_brackets_as_indices(tank):
    assert run(tank, {"k": [1.0]}, variables=["r[1]"]).variables == ("r[1]",)
    assert run(tank, {"k": [1.0]}, variables=["r[*]", "h"]).variables == ("r[1]", "r[2]", "h")
    assert run(tank, {"k": [1.0]}, variables=["?"]).variables == ("h", "q")
    with pytest.raises(DyadError, match="the pattern 'z\\*' matches no signal"):
        run(tank, {"k": [1.0]}, variables=["z*"])
