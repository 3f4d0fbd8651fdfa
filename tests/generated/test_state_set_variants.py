"""A generated module of a model whose state set switches carries every state set (derived at
compile time) and switches exactly as the in-process run does, on the VM and in C, in a process
that has only the runtime: the large-amplitude Cartesian pendulum over 20 s at rtol 1e-8, and a
3-body Cartesian chain (14 state sets)."""
import ast
import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from compiler import api
from compiler.cache.c_code import compile_c
from compiler.lower.ccodegen import find_compiler
from compiler.lower.codegen import write_module
from compiler.runtime.native import library
from tests.generated.fresh_process import run_json

MODELS = Path(__file__).resolve().parents[2] / "tests" / "models"
SPEC = "Hard.CartesianPendulumLarge"
SETTINGS = dict(rtol=1e-8, atol=1e-8, points=2001)
STOP = 20.0

# a generated module runs on the path the compiler takes for the same code (runtime.simulate's one
# choice, docs/runtime.md): on the VM CasADi's IDAS (no C library), in C the native IDAS driver
# where it is built; the in-process references run on the same code, and the two agree number
# for number and name the same integrator

needs_c_and_the_driver = pytest.mark.skipif(
    find_compiler() is None or library.driver_library()[0] is None,
    reason="no C compiler, or the native IDAS driver is not built (make install builds it)")


def run_module(module_dir: Path, name: str) -> dict:
    script = (
        "import json, sys\n"
        f"import {name} as m\n"
        f"r = m.simulate({STOP}, **{SETTINGS!r})\n"
        "out = {'x': list(r['x']), 'y': list(r['y']), 'lambda': list(r['lambda']),\n"
        "       'switches': [(s['time'], s['to']) for s in r.switches],\n"
        "       'codegen': m.model().metadata.get('codegen'),\n"
        "       'native': sorted(str(v.native_library is not None) for v in m.model().variants.values()),\n"
        "       'integrator': r.stats['integrator'],\n"
        "       'loaded': [k for k in ('sympy', 'lark', 'compiler') if k in sys.modules]}\n"
        "print(json.dumps(out))\n"
    )
    return run_json(script, module_dir)


@pytest.fixture(scope="module")
def compilation():
    return api.compile(SPEC, lib_dirs=(str(MODELS),))


@pytest.fixture(scope="module")
def in_process(compilation):
    return api.simulate_compiled(compilation, STOP, **SETTINGS, codegen="vm")


def switches(result) -> list:
    return [(s["time"], s["to"]) for s in result.switches]


def assert_same_run(out: dict, reference) -> None:
    assert out["loaded"] == []                         # the runtime alone: no sympy, lark, compiler
    assert out["integrator"] == reference.stats["integrator"]
    assert [(t, to) for t, to in out["switches"]] == switches(reference)
    for name in ("x", "y", "lambda"):
        assert np.array_equal(np.array(out[name]), reference[name]), name


def test_the_generated_module_switches_exactly_as_the_in_process_run(tmp_path, compilation, in_process):
    assert len(compilation.model.variants) == 1          # 2 state sets, the model's own first
    assert len(in_process.switches) >= 30               # about 30 switches in 20 s
    write_module(compilation.model, "pendulum_large", tmp_path, standalone=True)
    assert_same_run(run_module(tmp_path, "pendulum_large"), in_process)


@needs_c_and_the_driver
def test_c_code_of_every_state_set_switches_exactly_as_the_in_process_c_run(tmp_path, compilation):
    native = compile_c(compilation.model, tmp_path / "c-cache")
    assert native.native_library is not None
    assert all(v.native_library is not None for v in native.variants.values())
    in_c = api.simulate_compiled(dataclass_with_model(compilation, native), STOP, **SETTINGS)
    assert in_c.stats["integrator"] == "native"
    write_module(native, "pendulum_large_c", tmp_path / "module", standalone=True)
    assert len(list((tmp_path / "module").glob("pendulum_large_c_dae*.so"))) == 2
    out = run_module(tmp_path / "module", "pendulum_large_c")
    assert out["codegen"] == "c" and out["native"] == ["True"]
    assert_same_run(out, in_c)


def dataclass_with_model(compilation, model):
    return dataclasses.replace(compilation, model=model)


def test_the_module_text_holds_the_variants_as_plain_data(tmp_path, compilation):
    path = write_module(compilation.model, "pendulum_data", tmp_path)
    text = path.read_text()
    assert "_VARIANT_LIBRARIES = {}" in text            # no C libraries on the VM
    literal = text.split("_MODEL_JSON = ")[1].split("\n)\n")[0] + "\n)"
    payload = json.loads(ast.literal_eval(literal))
    assert payload["format_version"] == 4 and len(payload["variants"]) == 1


CHAIN_STOP, CHAIN_SETTINGS = 1.5, dict(rtol=1e-9, atol=1e-9, points=151)


@pytest.fixture(scope="module")
def chain_compilation(tmp_path_factory):
    from tests.hard.cartesian_chain import dyad_source
    path = tmp_path_factory.mktemp("chain") / "CartesianChain3.dyad"
    path.write_text(dyad_source(3, [1.3] * 3))
    return api.compile(f"{path}:CartesianChain3")


def run_chain_module(module_dir: Path, name: str) -> dict:
    script = (
        "import json, sys\n"
        f"import {name} as m\n"
        f"r = m.simulate({CHAIN_STOP}, **{CHAIN_SETTINGS!r})\n"
        "out = {name: list(r[name]) for name in ('x1', 'y1', 'x3', 'vy3', 'lambda2')}\n"
        "out['switches'] = [(s['time'], s['to']) for s in r.switches]\n"
        "out['native'] = sorted(str(v.native_library is not None) for v in m.model().variants.values())\n"
        "out['integrator'] = r.stats['integrator']\n"
        "out['loaded'] = [k for k in ('sympy', 'lark', 'compiler') if k in sys.modules]\n"
        "print(json.dumps(out))\n"
    )
    return run_json(script, module_dir)


def assert_same_chain_run(out: dict, reference) -> None:
    assert out["loaded"] == []
    assert out["integrator"] == reference.stats["integrator"]
    assert [(t, to) for t, to in out["switches"]] == switches(reference)
    for name in ("x1", "y1", "x3", "vy3", "lambda2"):
        assert np.array_equal(np.array(out[name]), reference[name]), name


def test_a_three_body_chain_carries_its_14_state_sets_and_its_module_switches_as_in_process(
        tmp_path, chain_compilation):
    # 656 structurally regular sets once, over the limit of 64, so the module carried one set only
    assert len(chain_compilation.model.variants) == 13
    in_process = api.simulate_compiled(chain_compilation, CHAIN_STOP, **CHAIN_SETTINGS, codegen="vm")
    assert len(in_process.switches) >= 3
    write_module(chain_compilation.model, "chain3", tmp_path, standalone=True)
    assert_same_chain_run(run_chain_module(tmp_path, "chain3"), in_process)


@needs_c_and_the_driver
def test_a_three_body_chain_in_c_switches_as_in_process_in_c(tmp_path, chain_compilation):
    native = compile_c(chain_compilation.model, tmp_path / "c-cache")
    assert all(v.native_library is not None for v in native.variants.values())
    in_c = api.simulate_compiled(dataclass_with_model(chain_compilation, native), CHAIN_STOP, **CHAIN_SETTINGS)
    assert in_c.stats["integrator"] == "native"
    write_module(native, "chain3_c", tmp_path / "module", standalone=True)
    out = run_chain_module(tmp_path / "module", "chain3_c")
    assert out["native"] == ["True"] * 13
    assert_same_chain_run(out, in_c)


def test_the_transistor_amplifier_module_switches_as_in_process(tmp_path):
    # 114 possible sets before folding and priorities (none carried); now 39, all carried
    compilation = api.compile("StructureModels.TransistorAmplifier",
                              lib_dirs=(str(Path(__file__).resolve().parents[1] / "structure" / "models"),))
    assert len(compilation.model.variants) == 38
    settings = dict(rtol=1e-8, atol=1e-8, points=201)
    in_process = api.simulate_compiled(compilation, 0.1, **settings, codegen="vm")
    assert len(in_process.switches) >= 10
    write_module(compilation.model, "transistor", tmp_path, standalone=True)
    script = ("import json, sys\nimport transistor as m\n"
              f"r = m.simulate(0.1, **{settings!r})\n"
              "out = {f'y{i}': list(r[f'y{i}']) for i in range(1, 9)}\n"
              "out['switches'] = [(s['time'], s['to']) for s in r.switches]\n"
              "out['loaded'] = [k for k in ('sympy', 'lark', 'compiler') if k in sys.modules]\n"
              "print(json.dumps(out))\n")
    out = run_json(script, tmp_path)
    assert out["loaded"] == []
    assert [(t, to) for t, to in out["switches"]] == switches(in_process)
    for i in range(1, 9):
        assert np.array_equal(np.array(out[f"y{i}"]), in_process[f"y{i}"]), i
