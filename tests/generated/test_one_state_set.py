"""A module generated from a model that needs dynamic state selection but carries its first state
set only (its state sets are more than the compiler builds ahead of time,
compiler/lower/state_set_enumeration.py; here the variants are removed to stand for that): it must
run while that set is valid and stop, saying so, where the compiler would switch."""
from pathlib import Path

import numpy as np
import pytest

from compiler import api, runtime
from compiler.lower.codegen import write_module
from tests.generated.fresh_process import run_json

ROOT = Path(__file__).resolve().parents[2]
MODELS = ROOT / "tests" / "structure" / "models"
SPEC = "StructureModels.CartesianPendulumHigh"
# the module is on the VM, so it runs CasADi's IDAS (runtime.simulate's choice; docs/runtime.md):
# the in-process references run on the VM too


@pytest.fixture(scope="module")
def module_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("generated")
    first_only = api.compile(SPEC, lib_dirs=(str(MODELS),)).model.replace(variants={})
    write_module(first_only, "cartesian_pendulum_high", out, standalone=True)
    return out


def run_module(module_dir: Path, stop: float) -> dict:
    script = (
        "import json, sys\n"
        "import cartesian_pendulum_high as m\n"
        "try:\n"
        f"    r = m.simulate({stop}, rtol=1e-10, atol=1e-10, points={int(stop * 100) + 1})\n"
        "    out = {'x': list(r['x']), 'y': list(r['y'])}\n"
        "except m._runtime.SimulationFailed as err:\n"
        "    out = {'error': str(err), 'time': err.time_reached}\n"
        "out['compiler_loaded'] = [k for k in ('sympy', 'lark', 'compiler') if k in sys.modules]\n"
        "print(json.dumps(out))\n"
    )
    return run_json(script, module_dir)


def test_module_matches_the_compiler_while_its_state_set_holds(module_dir):
    out = run_module(module_dir, 0.5)
    assert "error" not in out and out["compiler_loaded"] == []
    reference = api.simulate_compiled(api.compile(SPEC, lib_dirs=(str(MODELS),)), 0.5, rtol=1e-10, atol=1e-10,
                                      points=51, codegen="vm")
    assert reference.stats["state_switches"] == []            # the first switch is at about 0.57 s
    assert np.max(np.abs(np.array(out["x"]) - reference["x"])) < 1e-12


def test_module_stops_where_the_compiler_would_switch_state_sets(module_dir):
    out = run_module(module_dir, 1.0)
    reference = api.simulate_compiled(api.compile(SPEC, lib_dirs=(str(MODELS),)), 1.0, rtol=1e-10, atol=1e-10,
                                      points=101, codegen="vm")
    first_switch = reference.stats["state_switches"][0]["time"]
    assert out.get("time") == pytest.approx(first_switch, abs=1e-12)
    assert "stopped at t = " in out["error"] and "(y, v) degrades here" in out["error"]
    assert "simulate it with dyadc" in out["error"]


def test_the_compiler_can_still_run_the_first_state_set_alone():
    model = api.compile(SPEC, lib_dirs=(str(MODELS),)).model.replace(variants={})
    assert model.state_sets and model.state_sets[0]["candidates"]
    with pytest.raises(runtime.SimulationFailed, match="degrades here"):
        runtime.simulate(model, 1.0, rtol=1e-8, atol=1e-8, points=101)
