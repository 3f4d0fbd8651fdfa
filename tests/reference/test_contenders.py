"""The benchmark contenders run and report consistent results (cheap settings only)."""
import importlib.util
from pathlib import Path

import numpy as np
import pytest

CONTENDER_DIR = Path(__file__).resolve().parents[2] / "benchmarks" / "contenders"
REQUIRED_KEYS = {"problem", "method", "rtol", "atol", "time", "signals", "final", "wall_time_s",
                 "nfev", "njev", "nlu", "error"}


def load(name):
    spec = importlib.util.spec_from_file_location(f"_contender_{name}", CONTENDER_DIR / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def check_record(res, problem, method):
    assert REQUIRED_KEYS <= set(res)
    assert res["problem"] == problem and res["method"] == method
    for name, values in res["signals"].items():
        assert values.shape == res["time"].shape, name
        assert res["final"][name] == values[-1]
    assert res["nfev"] > 0


@pytest.mark.parametrize("method", ["Radau", "BDF", "LSODA"])
def test_pendulum_contender_error_shrinks_with_tolerance(method):
    mod = load("scipy_pendulum")
    loose, tight = mod.run(method, 1e-5, 1e-5), mod.run(method, 1e-9, 1e-9)
    check_record(tight, "pendulum", method)
    assert tight["error"] < loose["error"] and tight["error"] < 1e-5


@pytest.mark.parametrize("method", ["Radau", "BDF", "LSODA"])
def test_robertson_contender_reaches_reference(method):
    res = load("scipy_robertson").run(method, 1e-8, 1e-14)
    check_record(res, "robertson", method)
    assert res["error"] < 1e-4
    np.testing.assert_allclose(res["signals"]["y1"] + res["signals"]["y2"] + res["signals"]["y3"], 1.0, atol=1e-14)


@pytest.mark.parametrize("method", ["Radau", "BDF", "LSODA"])
def test_andrews_contender_reaches_reference(method):
    res = load("scipy_andrews").run(method, 1e-7, 1e-7)
    check_record(res, "andrews", method)
    assert res["error"] < 1e-3


def test_excavator_contender_short_horizon():
    res = load("scipy_excavator").run("BDF", 1e-6, 1e-6, t_end=1.0, points=101)
    check_record(res, "excavator", "BDF")
    assert res["error"] is None
    assert "boom_cyl.cylinder.p_a" in res["signals"] and "soil.m_load" in res["signals"]
    assert res["final"]["reference.s_boom"] < 0.49      # the boom has started to lower
