"""generated/ is committed: it must be exactly what the compiler writes today, and run without sympy or
lark, on the code and integrator `dyadc simulate` takes for the same model (issue 32 item 1)."""
import filecmp
import os
from pathlib import Path

import numpy as np
import pytest

from compiler.api import simulate
from compiler.cli.generate import GENERATED_MODELS, generate_all
from compiler.lower.ccodegen import find_compiler
from compiler.runtime.native import library
from tests.generated.fresh_process import run_json

ROOT = Path(__file__).resolve().parents[2]


def test_committed_generated_modules_are_up_to_date(tmp_path):
    written = generate_all(str(tmp_path))
    assert sorted(p.name for p in written) == sorted(f"{module}.py" for module in GENERATED_MODELS)
    for module in GENERATED_MODELS:
        name = f"{module}.py"
        assert filecmp.cmp(tmp_path / name, ROOT / "generated" / name, shallow=False), \
            f"generated/{name} is stale: run `make generate` and commit the result"
    committed = sorted(p.name for p in (ROOT / "generated").iterdir() if p.name != "__pycache__")
    assert committed == sorted(p.name for p in tmp_path.iterdir()), \
        "generated/ holds files the compiler no longer writes"


SCRIPT = (
    "import sys, json\n"
    "import generated.excavator as m\n"
    "r = m.simulate(1.0, points=11)\n"
    "heavy = [k for k in sys.modules if k.split('.')[0] in ('sympy', 'lark')]\n"
    "print(json.dumps({'heavy': heavy, 'runtime': m._runtime.__file__, 'states': len(m.STATES),\n"
    "                  'codegen': r.stats['codegen'], 'codegen_why': r.stats.get('codegen_why'),\n"
    "                  'integrator': r.stats['integrator'], 'why': r.stats.get('integrator_why'),\n"
    "                  'values': {name: list(r[name]) for name in m.VARIABLES}}))\n"
)


@pytest.mark.skipif(find_compiler() is None or library.driver_library()[0] is None,
                    reason="no C compiler, or the native IDAS driver is not built")
def test_the_generated_excavator_builds_its_c_library_and_runs_as_dyadc_simulate_does():
    """`make generate` writes the module without C code (its text must be reproducible); its first
    run builds the library with the build and cache `dyadc simulate` uses, so both run the same
    code on the native driver and agree to the last bit. Neither sympy nor lark is imported."""
    out = run_json(SCRIPT, ROOT)
    assert out["heavy"] == [] and out["runtime"].endswith("compiler/runtime/__init__.py")
    assert out["states"] == 19
    assert (out["codegen"], out["codegen_why"], out["integrator"], out["why"]) == ("c", None, "native", None)
    reference = simulate(GENERATED_MODELS["excavator"], 1.0, points=11)
    assert (reference.stats["codegen"], reference.stats["integrator"]) == ("c", "native")
    assert_same_values(out["values"], reference)


def test_without_a_c_compiler_the_generated_excavator_runs_on_the_vm_and_says_why(tmp_path):
    """The compiler lookup finds nothing ($CC unset, a PATH without gcc, cc or clang): the module
    runs on CasADi's VM with CasADi's IDAS, says why, and gives the compiler's own VM run's numbers."""
    env = {k: v for k, v in os.environ.items() if k != "CC"}
    env["PATH"] = str(tmp_path)                  # an empty folder: no compiler on it
    out = run_json(SCRIPT, ROOT, env=env)
    assert out["heavy"] == []
    assert (out["codegen"], out["codegen_why"]) == ("vm", "no C compiler (gcc, cc or clang) found")
    assert out["integrator"] == "casadi"
    assert out["why"] == "it is on CasADi's VM: no C compiler (gcc, cc or clang) found"
    reference = simulate(GENERATED_MODELS["excavator"], 1.0, points=11, codegen="vm")
    assert reference.stats["integrator"] == "casadi"
    assert_same_values(out["values"], reference)


def assert_same_values(values: dict, reference) -> None:
    """Every signal of the module's run equals the reference's to the last bit (NaN where it is NaN)."""
    assert len(values) == 631
    for name, column in values.items():
        assert np.array_equal(column, reference[name], equal_nan=True), name
