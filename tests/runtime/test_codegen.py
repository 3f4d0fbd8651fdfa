"""Generated Python modules: deterministic bytes, import isolation, same numbers as in-process."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from tests.runtime import runtime_systems as systems
from compiler import runtime
from compiler.cache.c_code import on_vm
from compiler.lower.codegen import write_module
from compiler.runtime.model_code import STANDALONE_WHY
from compiler.errors import DyadError
from compiler.lower.to_casadi import lower

REPO = Path(__file__).resolve().parents[2]


def run_python(code: str, env_extra: dict[str, str] | None = None, cwd: Path | None = None) -> str:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHASHSEED")}
    env.update(env_extra or {})
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                          cwd=cwd, timeout=120)
    assert done.returncode == 0, done.stderr
    return done.stdout


GENERATE = """
import sys
sys.path.insert(0, {repo!r})
from tests.runtime import runtime_systems as systems
from compiler.lower.codegen import write_module
from compiler.lower.to_casadi import lower
write_module(lower(systems.{system}()), {module!r}, {out!r}, standalone=True)
"""


@pytest.mark.parametrize("system", ["valve_tank", "pendulum_cartesian"])
def test_generated_module_is_byte_identical_across_hash_seeds(tmp_path, system):
    texts = []
    for seed in ("1", "4242"):
        out = tmp_path / f"seed{seed}"
        run_python(GENERATE.format(repo=str(REPO), system=system, module="model",
                                   out=str(out)), {"PYTHONHASHSEED": seed})
        texts.append(((out / "model.py").read_bytes(), (out / "dyad_runtime" / "__init__.py").read_bytes()))
    assert texts[0] == texts[1]
    assert texts[0][1] == Path(runtime.__file__).read_bytes()


def test_standalone_module_imports_no_compiler_and_matches_in_process(tmp_path):
    model = lower(systems.valve_tank())
    write_module(model, "valve_tank_model", tmp_path, standalone=True)
    code = """
import json, sys
import valve_tank_model as m
r = m.simulate(2.0, rtol=1e-9, atol=1e-12, points=11, params={"Kv": 6.0})
heavy = sorted({n.split(".")[0] for n in sys.modules} & {"sympy", "lark", "compiler"})
print(json.dumps({"h": r["h"].tolist(), "heavy": heavy, "params": m.PARAMETERS,
                  "variables": m.VARIABLES, "states": m.STATES, "codegen_why": r.stats.get("codegen_why")}))
"""
    data = json.loads(run_python(code, {"PYTHONPATH": str(tmp_path)}, cwd=tmp_path))
    assert data["heavy"] == []
    # written without a C library, and a standalone module builds none: the VM, as in process
    assert data["codegen_why"] == STANDALONE_WHY
    expected = runtime.simulate(on_vm(model), 2.0, rtol=1e-9, atol=1e-12, points=11, params={"Kv": 6.0})
    assert np.array_equal(np.array(data["h"]), expected["h"])
    assert data["params"] == dict(zip(model.parameter_names, model.parameter_defaults))
    assert data["variables"] == model.output_names and data["states"] == ["h"]


def test_generated_module_works_inside_a_package(tmp_path):
    package = tmp_path / "models_pkg"
    write_module(lower(systems.rc_circuit()), "rc", package, standalone=True)
    (package / "__init__.py").write_text("")
    code = """
import sys
from models_pkg import rc
r = rc.simulate(0.2, points=5)
print(rc.model().name, float(r["C.v"][-1]), "dyad_runtime" in sys.modules, rc._runtime.__name__)
"""
    name, final_voltage, top_level_runtime, runtime_name = run_python(code, {"PYTHONPATH": str(tmp_path)},
                                                                      cwd=tmp_path).split()
    assert name == "RC" and top_level_runtime == "False" and runtime_name == "models_pkg.dyad_runtime"
    assert float(final_voltage) == pytest.approx(10 * (1 - np.exp(-2.0)), rel=1e-5)


def test_invalid_module_name_is_refused(tmp_path):
    for name in ("my-model", "lambda", "dyad_runtime"):
        with pytest.raises(DyadError, match="not a valid Python module name"):
            write_module(lower(systems.rc_circuit()), name, tmp_path)


def test_a_module_without_standalone_runs_on_the_installed_runtime(tmp_path):
    model = lower(systems.rc_circuit())
    write_module(model, "rc", tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rc.py"]        # no copy of the runtime
    code = """
import sys, rc
r = rc.simulate(0.2, points=5)
print(rc._runtime.__name__, float(r["C.v"][-1]), "sympy" in sys.modules)
"""
    runtime_name, final_voltage, sympy_loaded = run_python(code, {"PYTHONPATH": str(tmp_path)},
                                                           cwd=tmp_path).split()
    assert runtime_name == "compiler.runtime" and sympy_loaded == "False"
    assert float(final_voltage) == runtime.simulate(model, 0.2, points=5)["C.v"][-1]


def test_compiled_model_written_twice_gives_identical_modules(tmp_path):
    from tests.runtime.lowered import compile_model
    for out in ("a", "b"):
        write_module(compile_model(systems.rc_circuit()), "rc", tmp_path / out)
    assert (tmp_path / "a" / "rc.py").read_bytes() == (tmp_path / "b" / "rc.py").read_bytes()
