"""A model with more state sets than the compiler derives one by one (a 5-body Cartesian chain:
122) carries its index-1 system once (compiler/lower/universal_variant.py), and the runtime makes
the model of any state set from it (compiler/runtime/universal.py). Checked: every variant the
compiler derives for a 3-body chain (14) and the pendulum is the one made from the universal
system (states and monitored levels); a generated module of the 5-body chain, in a process with the
runtime alone, switches where the in-process run does and agrees with it to the tolerance, on the
VM and with its first state set in C; the model round-trips through plain data."""
from __future__ import annotations

import dataclasses

import warnings
from pathlib import Path

import numpy as np
import pytest

from compiler import api, runtime
from compiler.cache.c_code import compile_c, on_vm
from compiler.lower.ccodegen import find_compiler
from compiler.lower.codegen import write_module
from compiler.lower.universal_variant import universal_model
from compiler.runtime.model_code import RUN_TIME_STATE_SET_WHY, STANDALONE_WHY
from compiler.runtime.native import library
from compiler.runtime.universal import variant_of
from compiler.runtime.variants import DUMMIES, SELECTION, variant_models
from tests.generated.fresh_process import run_json
from tests.hard.cartesian_chain import dyad_source

MODELS = Path(__file__).resolve().parents[2] / "tests" / "models"
STOP, SETTINGS = 3.0, dict(rtol=1e-8, atol=1e-8, points=301)
SIGNALS = ("x1", "y3", "x5", "vy5", "lambda2")
# a generated module runs on the path the compiler takes for the same code (runtime.simulate's one
# choice, docs/runtime.md): the in-process references run on the same code and name the same
# integrators (the VM: CasADi's IDAS; C: the native driver, and CasADi's IDAS on the state sets
# made at run time, which have no C library)


def chain(folder: Path, n: int):
    path = folder / f"CartesianChain{n}.dyad"
    path.write_text(dyad_source(n, np.linspace(1.0, 1.6, n)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")                # over the variant limit: said elsewhere
        return api.compile(f"{path}:CartesianChain{n}")


def monitored(model) -> list:
    return [(level["rows"], sorted(level["candidates"]),
             sorted(level["candidates"][j] for j in level["chosen"])) for level in model.state_sets]


@pytest.mark.parametrize("which", ["chain3", "pendulum"])
def test_every_compiled_variant_is_the_one_made_from_the_universal_system(tmp_path, which):
    compilation = (chain(tmp_path, 3) if which == "chain3"
                   else api.compile("Hard.CartesianPendulumLarge", lib_dirs=(str(MODELS),)))
    universal = universal_model(compilation.analysis, compilation.variant.reduced)
    selection = compilation.model.metadata[SELECTION]
    compiled = variant_models(compilation.model)
    assert len(compiled) == (14 if which == "chain3" else 2)
    for dummies, model in compiled.items():
        made = variant_of(universal, dummies, selection)
        assert sorted(made.state_names) == sorted(model.state_names), sorted(dummies)
        assert monitored(made) == monitored(model), sorted(dummies)
        assert made.metadata[DUMMIES] == sorted(dummies)


def test_a_run_switching_through_made_variants_matches_the_compiled_ones(tmp_path):
    compilation = chain(tmp_path, 3)
    reference = api.simulate_compiled(compilation, STOP, **SETTINGS, codegen="vm")
    # on the reference's path: the VM and CasADi's IDAS (in C the first state set would run natively)
    first = on_vm(compilation.model).replace(variants={}, universal=universal_model(
        compilation.analysis, compilation.variant.reduced))
    made = runtime.simulate(first, STOP, **SETTINGS)
    assert len(reference.switches) >= 4
    assert [s["to"] for s in made.switches] == [s["to"] for s in reference.switches]
    assert np.allclose([s["time"] for s in made.switches], [s["time"] for s in reference.switches],
                       rtol=0, atol=1e-6)
    for name in ("x1", "y2", "vx3", "lambda1"):
        assert np.max(np.abs(made[name] - reference[name])) < 1e-6 * max(1.0, np.max(np.abs(reference[name]))), name


@pytest.fixture(scope="module")
def chain5(tmp_path_factory):
    return chain(tmp_path_factory.mktemp("chain5"), 5)


@pytest.fixture(scope="module")
def chain5_in_process(chain5):
    return api.simulate_compiled(chain5, STOP, **SETTINGS, codegen="vm")


def run_module(module_dir: Path, name: str) -> dict:
    script = (
        "import json, sys\n"
        f"import {name} as m\n"
        f"r = m.simulate({STOP}, **{SETTINGS!r})\n"
        f"out = {{name: list(r[name]) for name in {SIGNALS!r}}}\n"
        "out['switches'] = [(s['time'], s['to']) for s in r.switches]\n"
        "out['native'] = m.model().native_library is not None\n"
        "out['integrator'] = r.stats['integrator']\n"
        "out['codegen_why'] = r.stats.get('codegen_why')\n"
        "out['loaded'] = [k for k in ('sympy', 'lark', 'compiler') if k in sys.modules]\n"
        "print(json.dumps(out))\n"
    )
    return run_json(script, module_dir)


def assert_same_run(out: dict, reference) -> None:
    assert out["loaded"] == []                         # the runtime alone: no sympy, lark, compiler
    assert out["integrator"] == reference.stats["integrator"]
    assert [to for _, to in out["switches"]] == [s["to"] for s in reference.switches]
    assert np.allclose([t for t, _ in out["switches"]], [s["time"] for s in reference.switches],
                       rtol=0, atol=1e-6)
    for name in SIGNALS:    # measured: within 3e-8 relative (rtol 1e-8)
        scale = max(1.0, float(np.max(np.abs(reference[name]))))
        assert np.max(np.abs(np.array(out[name]) - reference[name])) < 1e-6 * scale, name


def test_a_chain_over_the_limit_carries_its_universal_system(chain5, chain5_in_process):
    model = chain5.model
    assert not model.variants and model.universal is not None
    assert len(chain5_in_process.switches) >= 4
    payload = model.to_dict()
    assert payload["format_version"] == 5
    again = runtime.CompiledModel.from_dict(payload)
    assert again.universal.algebraic_names == model.universal.algebraic_names
    assert "universal" not in model.replace(universal=None).to_dict()
    assert model.replace(universal=None).to_dict()["format_version"] == 4


def test_its_generated_module_switches_as_the_in_process_run(tmp_path, chain5, chain5_in_process):
    write_module(chain5.model, "chain_five", tmp_path, standalone=True)
    out = run_module(tmp_path, "chain_five")
    # written without its C library, and a standalone module builds none: the VM, saying why
    assert out["native"] is False and out["codegen_why"] == STANDALONE_WHY
    assert_same_run(out, chain5_in_process)


@pytest.mark.skipif(find_compiler() is None or library.driver_library()[0] is None,
                    reason="no C compiler, or the native IDAS driver is not built (make install builds it)")
def test_its_c_module_switches_as_the_in_process_run(tmp_path, chain5):
    native = compile_c(chain5.model, tmp_path / "c-cache")
    assert native.native_library is not None and native.universal is not None
    in_c = api.simulate_compiled(dataclasses.replace(chain5, model=native), STOP, **SETTINGS)
    # the first state set in C on the native driver, the ones made at run time on the VM (never
    # built during a run: RUN_TIME_STATE_SET_WHY) and CasADi's IDAS; each switch says which (the
    # third goes back to the first state set)
    assert in_c.stats["integrator"] == "casadi, native"
    assert in_c.stats["integrator_why"] == f"it is on CasADi's VM: {RUN_TIME_STATE_SET_WHY}"
    made = ("vm", RUN_TIME_STATE_SET_WHY)
    assert [(s["codegen"], s.get("codegen_why")) for s in in_c.switches] == \
        [made, made, ("c", None), made, made]
    assert in_c.switches[2]["to"] == native.state_names
    write_module(native, "chain_five_c", tmp_path / "module", standalone=True)
    out = run_module(tmp_path / "module", "chain_five_c")
    assert out["native"] is True
    assert_same_run(out, in_c)
