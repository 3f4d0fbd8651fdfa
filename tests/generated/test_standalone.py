"""`dyadc compile --standalone`: the module and its copy of the runtime package run in a fresh
virtual environment that holds casadi and numpy and nothing else (no dyadc, no sympy, no lark).

The environment is made with `python -m venv --without-pip`; a .pth file gives it this project's
casadi and numpy through a folder of symlinks to just those two packages, so nothing is downloaded.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import casadi
import numpy
import numpy as np
import pytest

from compiler.api import simulate

ROOT = Path(__file__).resolve().parents[2]
MODEL = ROOT / "tests" / "models" / "ComponentTests" / "FallingBody.dyad"


@pytest.fixture(scope="module")
def bare_python(tmp_path_factory) -> Path:
    """The python of a fresh venv that can import casadi and numpy only."""
    base = tmp_path_factory.mktemp("bare")
    venv = base / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True, timeout=300)
    packages = base / "packages"
    packages.mkdir()
    for module in (casadi, numpy):
        folder = Path(module.__file__).parent
        (packages / folder.name).symlink_to(folder, target_is_directory=True)
        libs = folder.with_name(folder.name + ".libs")          # a wheel's bundled shared libraries
        if libs.is_dir():
            (packages / libs.name).symlink_to(libs, target_is_directory=True)
    python = venv / "bin" / "python"
    site = subprocess.run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                          capture_output=True, text=True, check=True, timeout=60).stdout.strip()
    Path(site, "casadi_numpy_only.pth").write_text(str(packages) + "\n", encoding="utf-8")
    return python


def _run(python: Path, script: str, cwd: Path, module_dir: Path) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTHON") and k != "VIRTUAL_ENV"}
    env["PYTHONPATH"] = str(module_dir)
    return subprocess.run([str(python), "-c", script], capture_output=True, text=True, cwd=cwd, env=env,
                          timeout=300)


def _compile(out: Path, *extra: str) -> None:
    done = subprocess.run([sys.executable, "-m", "compiler", "compile", str(MODEL), "-o", str(out),
                           "--name", "falling_body", *extra],
                          capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert done.returncode == 0, done.stderr


SCRIPT = """
import json, sys
import falling_body as m
r = m.simulate(1.0, points=5)
try:
    import compiler
    has_compiler = True
except ImportError:
    has_compiler = False
print(json.dumps({"y": list(r["body.r[2]"]), "runtime": m._runtime.__name__, "has_compiler": has_compiler,
                  "integrator": r.stats["integrator"], "why": r.stats.get("integrator_why"),
                  "heavy": sorted({k.split(".")[0] for k in sys.modules} & {"sympy", "lark", "matplotlib"})}))
"""


def test_a_standalone_module_runs_where_only_casadi_and_numpy_are_installed(bare_python, tmp_path):
    out = tmp_path / "module"
    _compile(out, "--standalone")
    assert (out / "dyad_runtime" / "__init__.py").is_file()
    empty = tmp_path / "empty"
    empty.mkdir()
    done = _run(bare_python, SCRIPT, empty, out)
    assert done.returncode == 0, done.stderr
    data = json.loads(done.stdout.strip().splitlines()[-1])
    assert data["runtime"] == "dyad_runtime" and not data["has_compiler"] and data["heavy"] == []
    # no dyadc where it runs, so no native IDAS driver (it is built into dyadc's environment): CasADi's
    # IDAS runs it and says why, as the compiler does on the VM
    assert data["integrator"] == "casadi" and data["why"].startswith("the native IDAS driver is not built")
    reference = simulate(str(MODEL), 1.0, points=5, codegen="vm")
    np.testing.assert_allclose(data["y"], reference["body.r[2]"], rtol=0, atol=1e-12)
    assert list(empty.iterdir()) == []


def test_every_module_of_the_standalone_copy_imports_with_casadi_and_numpy_alone(bare_python, tmp_path):
    """Catches an absolute `compiler.` import (or a top-level import of an optional package) in any
    module of the runtime package, including those the module itself loads only on demand."""
    out = tmp_path / "module"
    _compile(out, "--standalone")
    script = ("import importlib, json, pkgutil, dyad_runtime\n"
              "names = [m.name for m in pkgutil.walk_packages(dyad_runtime.__path__, 'dyad_runtime.')]\n"
              "for name in names:\n"
              "    importlib.import_module(name)\n"
              "print(json.dumps(names))\n")
    done = _run(bare_python, script, tmp_path, out)
    assert done.returncode == 0, done.stderr
    imported = json.loads(done.stdout.strip().splitlines()[-1])
    source = ROOT / "compiler" / "runtime"
    expected = set()
    for path in source.rglob("*.py"):
        parts = path.relative_to(source).with_suffix("").parts
        parts = parts[:-1] if parts[-1] == "__init__" else parts
        if parts and "__pycache__" not in parts:
            expected.add(".".join(("dyad_runtime",) + parts))
    assert set(imported) == expected


def test_the_standalone_copy_is_the_whole_runtime_package(tmp_path):
    out = tmp_path / "module"
    (out / "dyad_runtime").mkdir(parents=True)
    (out / "dyad_runtime" / "removed_long_ago.py").write_text("raise ImportError\n")
    _compile(out, "--standalone")
    source = ROOT / "compiler" / "runtime"
    expected = sorted(str(p.relative_to(source)) for p in source.rglob("*.py") if "__pycache__" not in p.parts)
    copied = sorted(str(p.relative_to(out / "dyad_runtime")) for p in (out / "dyad_runtime").rglob("*.py"))
    assert copied == expected
    for name in expected:
        assert (out / "dyad_runtime" / name).read_bytes() == (source / name).read_bytes()


def test_without_standalone_the_module_says_what_it_needs(bare_python, tmp_path):
    out = tmp_path / "module"
    _compile(out)
    assert not (out / "dyad_runtime").exists()
    done = _run(bare_python, SCRIPT, tmp_path, out)
    assert done.returncode != 0
    assert "needs dyadc's runtime package compiler.runtime" in done.stderr and "--standalone" in done.stderr
