"""A sweep's samples run on the path a `dyadc simulate` of the same model and parameters takes
(issue 32 item 1): the same code (compiled C where a C compiler is present, its library shipped
with the model) and the same integrator (the native IDAS driver where it can run the model), so
each sample equals the single run number for number; on the VM with CasADi's IDAS (the fallback)
the same holds. Each sample says which integrator ran it."""
from pathlib import Path

import numpy as np
import pytest

from compiler.api import simulate_compiled
from compiler.compiled_runs import model_for_runs
from compiler.pipeline import compile_spec
from compiler.sweep import SweepOptions, sweep
from compiler.sweep.worker import ModelPayload, load_model
from tests.conftest import INTEGRATOR_OF
from tests.sweep.models import write_decay

RATES = [0.5, 1.0, 2.0]
RUN = dict(stop=2.0, points=21, rtol=1e-6, atol=1e-6)


@pytest.fixture(scope="module")
def decay(each_codegen, tmp_path_factory):
    return compile_spec(str(write_decay(tmp_path_factory.mktemp("decay"))))


@pytest.fixture(scope="module")
def singles(decay):
    return [simulate_compiled(decay, RUN["stop"], points=RUN["points"], rtol=RUN["rtol"],
                              atol=RUN["atol"], params={"k": k}) for k in RATES]


def test_a_three_point_sweep_equals_three_simulate_runs_number_for_number(decay, singles, each_codegen):
    result = sweep(decay, {"k": RATES}, SweepOptions(serial=True, variables=["x", "y[2]"], **RUN))
    integrator = INTEGRATOR_OF[each_codegen]
    assert [single.stats["integrator"] for single in singles] == [integrator] * 3
    assert result.stats["integrator"] == integrator
    for sample, single in zip(range(3), singles):
        outcome = result.outcomes[sample]
        assert outcome.ok and outcome.integrator == integrator
        assert np.array_equal(outcome.time, single.time)
        for name in ("x", "y[2]"):
            assert np.array_equal(outcome.values[name], single[name]), (sample, name)


def test_a_worker_loads_the_shipped_c_library_of_a_model_on_c(decay, each_codegen):
    """The payload carries the library's bytes: a worker on another machine has no C cache."""
    on_code = model_for_runs(decay, None)
    payload = ModelPayload.of(on_code)
    assert sorted(payload.libraries) == ([""] if each_codegen == "c" else [])
    loaded = load_model(payload)
    if each_codegen == "c":
        assert loaded.native_library != on_code.native_library
        assert Path(loaded.native_library).read_bytes() == Path(on_code.native_library).read_bytes()
    else:
        assert loaded.native_library is None


def test_dyadc_sweep_names_the_integrator_its_samples_ran_on(decay, each_codegen, tmp_path, capsys):
    from compiler.cli import main
    source = write_decay(tmp_path)
    assert main(["sweep", str(source), "--stop", "1", "--points", "5", "--serial", "-p", "k=[1,2]"]) == 0
    named = {"c": "native IDAS", "vm": "CasADi's IDAS"}      # (each_codegen asks for it by name)
    assert f"ran on serial, on {named[each_codegen]}\n" in capsys.readouterr().err
