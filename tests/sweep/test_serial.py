"""Sweeps run here, without Dask: results against the closed form, isolated failures, refusals,
tables and files, the plot, the progress bar."""
import math
import sys
import subprocess
from pathlib import Path

import numpy as np
import pytest

from compiler.errors import DyadError
from compiler.pipeline import compile_spec
from compiler.sweep import SweepOptions, sweep
from tests.sweep.models import decay_level, write_decay

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def decay(tmp_path_factory):
    return compile_spec(str(write_decay(tmp_path_factory.mktemp("decay"))))


def run(compilation, design, **options):
    options.setdefault("stop", 1.0)
    options.setdefault("points", 11)
    return sweep(compilation, design, SweepOptions(serial=True, **options))


def test_every_sample_follows_the_closed_form(decay):
    result = run(decay, {"k": [0.5, 1.0, 2.0], "x0": [1.0, 3.0]}, metrics=["final(x)", "low=min(x)"])
    assert len(result) == 6 and not result.failed and result.complete
    for outcome in result.succeeded:
        p = result.parameter_values(outcome.sample)
        exact = decay_level(outcome.time, p["k"], 0.0, p["x0"])
        assert np.allclose(outcome.values["x"], exact, rtol=1e-5, atol=1e-7)
        assert outcome.metrics["final(x)"] == outcome.values["x"][-1]
        assert outcome.metrics["low"] == pytest.approx(exact[-1], rel=1e-5)


def test_a_failing_sample_is_recorded_with_its_reason_and_time_and_the_others_finish(decay):
    result = run(decay, {"c": [0.0, -2.0, 0.5], "k": [1.0, 2.0]}, metrics=["final(x)"])
    assert len(result) == 6
    failed = {o.sample: o for o in result.failed}
    assert sorted(failed) == [2, 3]                     # c = -2 with k = 1 and k = 2
    for sample, outcome in failed.items():
        p = result.parameter_values(sample)
        # the level reaches its min = 0 at ln((x0 - c/k) / (-c/k)) / k
        expected = math.log((1 - p["c"] / p["k"]) / (-p["c"] / p["k"])) / p["k"]
        assert outcome.time_reached == pytest.approx(expected, abs=2e-5)   # located to rtol
        assert "outside its declared min" in outcome.reason
    table = result.samples()
    assert table["status"] == ["ok", "ok", "failed", "failed", "ok", "ok"]
    assert np.isnan(table["final(x)"][2]) and np.isfinite(table["final(x)"][4])
    assert np.isnan(table["failed_at"][0]) and table["failed_at"][3] == failed[3].time_reached
    assert set(result.trajectories()["sample"]) == {0, 1, 4, 5}
    assert "2 failed" in result.summary() and "sample 2 (c=-2, k=1) failed at t = 0.40546" in result.summary()


def test_structural_final_unknown_and_unused_parameters_are_refused_by_name(decay):
    with pytest.raises(DyadError) as info:
        run(decay, {"n": [1, 2], "f": [1, 3], "kk": [1, 2]})
    text = info.value.format()
    assert "`n` is a structural parameter" in text
    assert "`f` is final and cannot be changed" in text
    assert "`kk` is not a parameter of Decay (did you mean 'k'?)" in text
    assert "Decay.dyad:9:3: note: `n` is declared here" in text      # its declaration, not its docstring


def test_fixed_overrides_apply_to_every_sample_and_are_checked(decay):
    result = run(decay, {"k": [1.0, 2.0]}, params={"x0": 2.0})
    for outcome in result.succeeded:
        assert outcome.values["x"][0] == pytest.approx(2.0)
    with pytest.raises(DyadError, match="`f` is final"):
        run(decay, {"k": [1.0]}, params={"f": 3.0})


def test_unknown_signals_and_metric_names_fail_before_any_run(decay):
    with pytest.raises(DyadError, match=r"`xx` is not a signal of Decay \(did you mean 'x'\?\)"):
        run(decay, {"k": [1.0]}, variables=["xx"])
    with pytest.raises(DyadError, match="`y3` is not a signal"):
        run(decay, {"k": [1.0]}, metrics=["max(y3)"])


def test_tables_written_as_parquet_and_csv_hold_the_same_numbers(decay, tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    result = run(decay, {"k": [1.0, 2.0], "c": [0.0, -2.0]}, metrics=["final(x)"],
                 variables=["x", "y[2]"])
    trajectories, samples = result.write(tmp_path / "out" / "s.parquet")
    assert samples == tmp_path / "out" / "s.samples.parquet"
    table = pq.read_table(trajectories).to_pydict()
    assert list(table) == ["sample", "k", "c", "time", "x", "y[2]"]
    columns = result.trajectories()
    for name in table:
        assert np.array_equal(np.asarray(table[name]), columns[name])
    assert pq.read_table(samples).to_pydict()["status"] == ["ok", "failed", "ok", "failed"]
    result.write(tmp_path / "s.csv")
    lines = (tmp_path / "s.csv").read_text().splitlines()
    assert lines[0] == "sample,k,c,time,x,y[2]" and len(lines) == 1 + 2 * 11
    row = lines[5].split(",")
    assert float(row[4]) == columns["x"][4]                       # %.17g: exact round trip
    header = (tmp_path / "s.samples.csv").read_text().splitlines()[0]
    assert header == "sample,k,c,status,reason,failed_at,seconds,worker,final(x)"
    assert not list(tmp_path.glob(".*.tmp"))                       # atomic writes leave nothing behind


def test_to_pandas_is_lazy_and_says_when_pandas_is_missing(decay, monkeypatch):
    result = run(decay, {"k": [1.0, 2.0]})
    monkeypatch.setitem(sys.modules, "pandas", None)              # as if it were not installed
    with pytest.raises(DyadError, match="needs pandas"):
        result.to_pandas()
    monkeypatch.undo()
    pd = pytest.importorskip("pandas")
    frame = result.to_pandas()
    assert isinstance(frame, pd.DataFrame) and list(frame.columns) == ["sample", "k", "time", "x"]


def test_a_progress_callback_sees_every_sample_and_changes_no_number(decay, capsys):
    from compiler.cli.progress import SweepProgress
    design = {"k": [0.5, 1.0, 1.5], "c": [0.2, -2.0]}
    quiet = run(decay, design, points=401, stop=3.0)
    assert capsys.readouterr().err == ""                  # the sweep itself prints nothing
    bar = SweepProgress(6, enabled=True)
    loud = run(decay, design, points=401, stop=3.0, on_sample=lambda o: bar.advance(1, 0 if o.ok else 1))
    bar.close()
    assert "6/6 samples, 3 failed" in capsys.readouterr().err
    for sample, outcome in quiet.outcomes.items():
        other = loud.outcomes[sample]
        assert outcome.ok == other.ok and outcome.time_reached == other.time_reached
        for name in outcome.values:
            assert np.array_equal(outcome.values[name], other.values[name])


def test_the_summary_plot_uses_no_pyplot(tmp_path):
    script = f"""
import sys, matplotlib
backend = dict.__getitem__(matplotlib.rcParams, "backend")   # get_backend() itself would load pyplot
from compiler.sweep import SweepOptions, sweep
from compiler.pipeline import compile_spec
r = sweep(compile_spec({str(tmp_path / 'Decay.dyad')!r}),
          {{"k": [0.5, 1, 2], "c": [0.0, 0.3]}},
          SweepOptions(stop=2.0, points=21, serial=True, metrics=["final(x)"]))
r.plot({str(tmp_path / 'plot.png')!r})
print("pyplot" if "matplotlib.pyplot" in sys.modules else "no pyplot", backend == dict.__getitem__(matplotlib.rcParams, "backend"))
"""
    write_decay(tmp_path)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=ROOT,
                          timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["no", "pyplot", "True"]
    png = (tmp_path / "plot.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10_000
