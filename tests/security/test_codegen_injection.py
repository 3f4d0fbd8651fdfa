"""Names and texts of a model reach generated code only as data (issue 19, item 2).

A folder, file, component, variable or string name that looks like Python (or C) must never run
when the generated module is imported: each test compiles such a model with the real CLI, imports
the result in a fresh process and checks that no marker file appeared and that the module works.
"""
from __future__ import annotations

import ast
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from compiler.cache.c_code import compile_c
from compiler.lower import ccodegen
from compiler.lower.codegen import docstring_text, module_source
from compiler.lower.to_casadi import lower
from compiler.runtime import CompiledModel
from tests.runtime import runtime_systems as systems

ROOT = Path(__file__).resolve().parents[2]


def _touch(marker: str, quote: str = '"') -> str:
    return f'__import__({quote}os{quote}).system({quote}touch {marker}{quote})'


# Each tries to end the string it lands in (docstring, literal, comment) and run a command.
HOSTILE_FOLDER = (f'a"""; {_touch("INJECTED_DQ")}; """b'
                  f"'''; {_touch('INJECTED_SQ', chr(39))}; '''\\\\\"; {_touch('INJECTED_BS')} #")
HOSTILE_FILE = f'Osc"""; {_touch("INJECTED_FILE")}; """ *\\ #.dyad'

MODEL = '''"""Doc \\"\\"\\"; __import__('os').system('touch INJECTED_DOC') \\\\"""
component Osc
  "\\"\\"\\"; __import__('os').system('touch INJECTED_STRING')"
  parameter ω₀::Real = 2.0
  variable __import__::Real
  variable exec::Real
relations
  initial __import__ = 1.0
  initial exec = 0.0
  der(__import__) = exec
  der(exec) = -ω₀^2 * __import__
metadata {"Dyad": {"doc": "*/ \\"\\"\\"; __import__('os').system('touch INJECTED_META')"}}
end
'''


def _markers(root: Path) -> list[str]:
    return sorted(str(p) for p in root.rglob("INJECTED*"))


def _dyadc(args: list[str], cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "compiler", *args], capture_output=True, text=True,
                          cwd=cwd, timeout=300)


def _import_and_run(module: str, module_dir: Path, cwd: Path) -> dict:
    script = (f"import json, sys\nsys.path.insert(0, {str(module_dir)!r})\nimport {module} as m\n"
              "r = m.simulate(1.0, points=3, rtol=1e-10, atol=1e-12)\n"
              "print(json.dumps({'name': m.NAME, 'doc': m.__doc__, 'states': m.STATES,\n"
              "                  'params': m.PARAMETERS, 'x': list(r['__import__']),\n"
              "                  'native': m.model().native_library is not None}))\n")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=cwd,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


@pytest.fixture
def hostile_library(tmp_path) -> tuple[Path, Path]:
    """(library root, model file) with a hostile folder and a hostile file name."""
    root = tmp_path / "lib"
    folder = root / HOSTILE_FOLDER
    folder.mkdir(parents=True)
    model_file = folder / HOSTILE_FILE
    model_file.write_text(MODEL, encoding="utf-8")
    return root, model_file


def _check_module(out: dict, tmp_path: Path) -> None:
    assert _markers(tmp_path) == []
    assert out["name"] == f"{HOSTILE_FOLDER}.Osc"                    # the name survives as data
    assert HOSTILE_FOLDER in out["doc"]
    assert out["states"] == ["__import__", "exec"] and out["params"] == {"ω₀": 2.0}
    np.testing.assert_allclose(out["x"], np.cos(2.0 * np.array([0.0, 0.5, 1.0])), atol=1e-8)


@pytest.mark.parametrize("standalone", [False, True])
def test_hostile_names_do_not_run_when_the_module_is_imported(tmp_path, hostile_library, standalone):
    root, model_file = hostile_library
    out_dir = tmp_path / "out"
    done = _dyadc(["compile", f"{model_file}:Osc", "--lib", str(root), "-o", str(out_dir), "--name", "osc"]
                  + (["--standalone"] if standalone else []), tmp_path)
    assert done.returncode == 0, done.stderr
    assert (out_dir / "osc.py").is_file() and _markers(tmp_path) == []
    _check_module(_import_and_run("osc", out_dir, tmp_path), tmp_path)
    ast.parse((out_dir / "osc.py").read_text(encoding="utf-8"))   # still well-formed Python


@pytest.mark.skipif(ccodegen.find_compiler() is None, reason="no C compiler")
def test_hostile_names_never_reach_the_c_code(tmp_path, hostile_library, monkeypatch):
    from compiler.lower.codegen import write_module
    from compiler.pipeline import compile_spec
    monkeypatch.setenv("DYADC_CACHE", str(tmp_path / "cache"))
    root, model_file = hostile_library
    model = compile_spec(f"{model_file}:Osc", [str(root)]).model
    source = ccodegen.c_source(model)
    for text in ("INJECTED", "__import__", "ω₀", "\"\"\""):
        assert text not in source
    native = compile_c(model)
    assert native.metadata["codegen"] == "c"
    write_module(native, "osc_native", tmp_path / "out")
    out = _import_and_run("osc_native", tmp_path / "out", tmp_path)
    assert out["native"]
    _check_module(out, tmp_path)


@pytest.mark.parametrize("name", ["os; import os", "class", "dyad_runtime", "9lives", "ösc"])
def test_a_module_name_that_is_not_a_plain_identifier_is_refused(tmp_path, hostile_library, name):
    root, model_file = hostile_library
    done = _dyadc(["compile", f"{model_file}:Osc", "--lib", str(root), "-o", str(tmp_path / "out"),
                   "--name", name], tmp_path)
    assert done.returncode == 1
    assert "error:" in done.stderr and "not a valid Python module name" in done.stderr
    assert "Traceback" not in done.stderr
    assert not (tmp_path / "out").exists() or not list((tmp_path / "out").glob("*.py"))


# ---------------------------------------------------------------- any text at all, in-process

_BASE = lower(systems.pendulum_angle())


def _renamed(name: str, states: list[str]) -> CompiledModel:
    data = _BASE.to_dict()
    renames = dict(zip(data["state_names"], states))
    data.update(name=name, state_names=states,
                output_names=[renames.get(n, n) for n in data["output_names"]],
                parameter_names=[f"{states[0]}.{n}" for n in data["parameter_names"]])
    return CompiledModel.from_dict(data)


def _shape(tree: ast.Module) -> list[str]:
    """Top-level statement kinds and the names they bind: what an injection would change."""
    return [type(node).__name__ + ":" + ",".join(sorted(
        t.id for n in ast.walk(node) for t in [n] if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store)))
        for node in tree.body]


@settings(max_examples=150, deadline=None)
@given(name=st.text(max_size=40), state=st.text(min_size=1, max_size=20))
def test_any_text_as_a_name_is_data_in_the_generated_module(name, state):
    states = [state, state + "'"]
    source = module_source(_renamed(name, states), "model", standalone=True)
    tree = ast.parse(source)
    assert _shape(tree) == _shape(ast.parse(module_source(_BASE, "model", standalone=True)))
    assert ast.get_docstring(tree, clean=False).startswith(f"Generated by dyadc from model {name}. ")
    assignments = {node.targets[0].id: node.value for node in tree.body
                   if isinstance(node, ast.Assign) and isinstance(node.targets[0], ast.Name)}
    assert ast.literal_eval(assignments["NAME"]) == name
    assert ast.literal_eval(assignments["STATES"]) == states
    payload = json.loads(ast.literal_eval(assignments["_MODEL_JSON"]))
    assert payload["name"] == name and payload["state_names"] == states


@given(st.text())
def test_docstring_escaping_reads_back_exactly(text):
    assert ast.literal_eval('"""' + docstring_text(text) + '"""') == text
