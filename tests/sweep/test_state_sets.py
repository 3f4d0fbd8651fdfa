"""A model whose state set switches during the run (the Cartesian pendulum swinging past the
horizontal) sweeps like any other: its compiled model carries every state set (built at compile
time, on the client) and switches among them with the runtime only; each sample gives,
number for number, what `simulate` of a fresh compilation gives (serial engine here; the Dask
engine in test_dask.py)."""
from pathlib import Path

import numpy as np
import pytest

from compiler import api
from compiler.pipeline import compile_spec
from compiler.sweep import SweepOptions, sweep

ROOT = Path(__file__).resolve().parents[2]
PENDULUM = ("StructureModels.CartesianPendulumHigh", [str(ROOT / "tests" / "structure" / "models")])
GRID = {"L": [0.5, 2.0], "theta0": [2.0, 2.5]}
RUN = dict(stop=3.0, points=61, variables=["x", "y", "T"], metrics=["final(x)", "top=max(y)"])


def pendulum():
    return compile_spec(*PENDULUM)


def separate_runs(design):
    """Each sample run on its own fresh compilation by the compiler's own simulate, on the path
    it chooses, which a sweep's workers take too (docs/sweeps.md)."""
    runs = {}
    for sample, params in enumerate(design):
        result = api.simulate_compiled(pendulum(), RUN["stop"], points=RUN["points"], params=params)
        runs[sample] = result
    return runs


def assert_equal_to_separate_runs(result, runs):
    assert sorted(result.outcomes) == sorted(runs)
    for sample, reference in runs.items():
        outcome = result.outcomes[sample]
        assert outcome.ok, outcome.reason
        assert np.array_equal(outcome.time, reference.time)
        for name in RUN["variables"]:
            assert np.array_equal(outcome.values[name], reference[name]), (sample, name)
        assert outcome.metrics["final(x)"] == reference["x"][-1]


@pytest.fixture(scope="module")
def reference():
    design = [{"L": L, "theta0": th} for L in GRID["L"] for th in GRID["theta0"]]
    runs = separate_runs(design)
    assert all(len(run.switches) >= 2 for run in runs.values())     # every sample switches, back and forth
    return runs


def test_a_switching_model_sweeps_serially_as_separate_runs(reference):
    compilation = pendulum()
    assert compilation.dynamic
    result = sweep(compilation, GRID, SweepOptions(serial=True, **RUN))
    assert_equal_to_separate_runs(result, reference)


def test_its_compiled_model_alone_carries_its_state_sets_and_sweeps_the_same(reference):
    compiled = pendulum().model
    assert compiled.state_sets and len(compiled.variants) >= 1      # every other state set travels with it
    result = sweep(compiled, GRID, SweepOptions(serial=True, **RUN))
    assert_equal_to_separate_runs(result, reference)
