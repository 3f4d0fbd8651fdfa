"""The issue-32 benchmark (benchmarks/bench_native_targets.py) at tiny sizes, so that it cannot rot:
the event tests are read from their file, one of them runs on both integrators, and the section
renders every target with its verdict into a doc block."""
from __future__ import annotations

import sys
from pathlib import Path

import pytest

from compiler.runtime.native import library

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
import bench_native_targets  # noqa: E402
from suite import native_events  # noqa: E402

needs_driver = pytest.mark.skipif(library.driver_library()[0] is None, reason="the native IDAS driver is not built")


def test_the_event_tests_are_read_from_their_file():
    tank = next(case for case in native_events.event_test_cases() if case["name"] == "Tank")
    assert tank["test"] == "test_a_tank_drains_until_it_is_empty_and_stays_empty"
    assert tank["stop"] == 10.0 and tank["settings"] == {"rtol": 1e-8, "atol": 1e-10, "points": 11}
    assert "der(h) = if h > 0 then -q / A else 0" in tank["body"]


def test_event_differences_name_the_labels_whose_counts_differ():
    native = [{"time": 1.0, "event": "x < 1"}, {"time": 2.0 + 3e-8, "event": "x < 1"}, {"time": 2.0, "event": "f"}]
    casadi = [{"time": 1.0, "event": "x < 1"}, {"time": 2.0, "event": "x < 1"}]
    found = native_events.event_differences(native, casadi, rtol=1e-8, atol=1e-10)
    assert found["unmatched"] == [("f", 1, 0)]
    assert found["event_share"] == pytest.approx(3e-8 / (1e-10 + 2e-8), rel=1e-6)


@pytest.fixture(scope="module")
def tank_events():
    return native_events.measure(1, lambda line: None, corpus=None, only={"Tank"})


@needs_driver
def test_the_tank_runs_natively_in_fewer_steps_with_the_same_numbers(tank_events):
    (row,) = tank_events["rows"]
    assert row["integrator"] == "native"
    assert row["native_steps"] < row["casadi_steps"] and row["same"]
    assert tank_events["notes"] == ["the detailed op-amp was not run: no corpus given (--corpus DIR)"]


def excavator_data() -> dict:
    scipy = "scipy Radau (make bench's: one solve_ivp call)"
    stats = {"steps": 2634, "residual_evaluations": 6389, "jacobian_evaluations": 193, "newton_iterations": 6389}
    return {"scipy": [{"name": scipy, "tip": 3.3e-7, "time": 3.0}], "scipy_rtol": 1e-6, "notes": [],
            "dyadc": [{"name": "dyadc (C, native IDAS)", "against": scipy, "rtol": 3e-8, "tip": 2.98e-7,
                       "time": 0.15, "speedup": 20.0, "stats": stats, "integrator": "native"}],
            "bare": {"rtol": 3e-8, "time": 0.09, "ratio": 0.15 / 0.09, "stats": stats},
            "profile": [("library.py:115(advance)", 47.2, 47.4)], "load": ("1.0", "2.0")}


def switching_data() -> dict:
    return {"ours": 0.068, "integrator": "native", "switches": 30, "ours_error": 9e-6, "rtol_after_switch": 1e-10,
            "ours_stats": {"steps": 8696, "segments": 31}, "profile_total": 0.26,
            "matched": {"rtol": 1e-8, "error": 5.8e-6, "time": 0.0093, "steps": 2169},
            "phases": {"state-set switches": 0.099, "checks": 0.0}, "load": ("1.0", "2.0")}


@needs_driver
def test_the_section_gives_every_target_its_verdict_and_the_profile_where_missed(tank_events, tmp_path):
    data = {"repeats": 1, "stamp": "2026-11-28 14:00 UTC", "sundials": "7.1.1", "excavator": excavator_data(),
            "switching": switching_data(), "events": {**tank_events, "load": ("1.0", "2.0")}}
    section = bench_native_targets.render(data)
    table = section.split("| target | measured | met |\n|---|---|---|\n")[1].split("\n\n")[0]
    rows = table.splitlines()
    assert [row.rsplit("|", 2)[1].strip() for row in rows] == ["no", "no", "no", "yes"]
    assert "20x (rtol 3e-08, 150.0 ms against 3000 ms)" in rows[0] and "1.67x" in rows[1]
    assert "`library.py:115(advance)` 47.2 ms" in section and "state-set switches 99 ms" in section
    doc = tmp_path / "benchmarks.md"
    doc.write_text("# Benchmarks\n", encoding="utf-8")
    bench_native_targets.write_doc(section, doc)
    bench_native_targets.write_doc(section, doc)
    text = doc.read_text(encoding="utf-8")
    assert text.count(bench_native_targets.BEGIN) == 1 and text.count(f"## {bench_native_targets.HEADING}") == 1


def test_a_contender_named_by_path_joins_both_scipy_radau_contenders():
    from suite.native_excavator import scipy_contenders
    from suite.problems import CONTENDERS, Excavator
    made = scipy_contenders(Excavator(check_reference=False), CONTENDERS / "scipy_excavator.py")
    assert [c.name for c in made] == ["scipy Radau (make bench's: one solve_ivp call)",
                                      "scipy Radau (the reference model as written: restarted at its waypoints)",
                                      "scipy Radau (scipy_excavator)"]
    assert [c.options for c in made] == [{}, {"split_at_waypoints": True}, {}] and callable(made[2].module.run)


@needs_driver
def test_a_signal_that_amplifies_a_states_error_is_judged_against_a_tighter_run(tmp_path):
    """h = a limited 1e5 q differs between the paths by far more than its own tolerance units
    (tests/native/test_gain_amplified_error.py); the comparison then asks a run at 1e4 times
    smaller tolerances, and both paths are about as far from it (measured: s off by 0.43 natively
    and 0.20 on CasADi's IDAS, h by 0.31 and 0.15)."""
    from compiler import api
    from tests.native.test_gain_amplified_error import SOURCE
    path = tmp_path / "GainLimiter.dyad"
    path.write_text(SOURCE, encoding="utf-8")
    row = native_events.compare("gain", api.compile(str(path)), 0.01,
                                {"rtol": 1e-6, "atol": 1e-6, "points": 1001}, repeats=1)
    assert row["worst"] > native_events.AGREEMENT and sorted(row["offs"]) == ["h", "s"]
    for native_off, casadi_off in row["offs"].values():
        assert 0 < native_off <= 3 * casadi_off
    assert row["same"]
