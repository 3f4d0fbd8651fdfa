"""`pip install` (not editable) gives a working compiler (issue 13).

A wheel is built from a copy of the sources (so nothing is written into the repository), installed
into a fresh virtual environment, and run from an empty folder outside the repository. The fresh
environment sees the project's dependencies (sympy, casadi, ...) through a .pth file that points to
a folder holding only those (links into the project's site-packages, without dyadc itself and
without its editable-install hook), so nothing is downloaded and the test stays fast.
"""
from __future__ import annotations

import csv
import json
import os
import shutil
import subprocess
import sys
import sysconfig
import textwrap
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXCAVATOR = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"
GOLDEN = ROOT / "tests" / "golden" / f"{EXCAVATOR}.dig_cycle.csv"
SOURCE_FOLDERS = ("compiler", "components")
TIMEOUT = 300


def _run(command: list, **kwargs) -> subprocess.CompletedProcess:
    run = subprocess.run([str(c) for c in command], capture_output=True, text=True,
                         timeout=TIMEOUT, **kwargs)
    assert run.returncode == 0, f"{command} failed:\n{run.stdout}\n{run.stderr}"
    return run


def _copy_sources(target: Path) -> None:
    """The files a build reads: the top-level files (pyproject.toml, setup.py, README.md, ...)
    and the package folders, without caches."""
    target.mkdir()
    for path in ROOT.iterdir():
        if path.is_file():
            shutil.copy2(path, target / path.name)
    for folder in SOURCE_FOLDERS:
        shutil.copytree(ROOT / folder, target / folder,
                        ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))


def _dependencies_only(target: Path) -> Path:
    """A folder of links to everything in this interpreter's site-packages except dyadc itself
    (its package, its metadata, its editable-install hook) and .pth files."""
    target.mkdir()
    site_dirs = {Path(sysconfig.get_paths()[key]).resolve() for key in ("purelib", "platlib")}
    for site in site_dirs:
        for entry in site.iterdir():
            name = entry.name
            if (name in ("compiler", "__pycache__") or name.endswith(".pth")
                    or name.startswith(("dyadc-", "dyadc.", "__editable__"))
                    or (target / name).exists()):
                continue
            (target / name).symlink_to(entry)
    return target


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """(fresh environment, the wheel): dyadc built as a wheel and installed into a new venv."""
    base = tmp_path_factory.mktemp("wheel")
    sources, dist, env = base / "src", base / "dist", base / "env"
    _copy_sources(sources)
    _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "--no-index",
          "--quiet", "-w", dist, sources])
    (wheel,) = dist.glob("dyadc-*.whl")
    _run([sys.executable, "-m", "venv", "--without-pip", env])
    _run([sys.executable, "-m", "pip", "--python", env / "bin" / "python", "install", "--no-deps",
          "--no-index", "--quiet", wheel])
    site = Path(_run([env / "bin" / "python", "-c",
                      "import sysconfig; print(sysconfig.get_paths()['purelib'])"]).stdout.strip())
    (site / "dyadc_test_dependencies.pth").write_text(f"{_dependencies_only(base / 'deps')}\n")
    return env, wheel


@pytest.fixture
def outside(tmp_path):
    """An empty working folder outside the repository and an environment that does not point
    back into it."""
    work = tmp_path / "work"
    work.mkdir()
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "PYTHONHOME", "DYADC_PATH", "VIRTUAL_ENV")}
    env["DYADC_CACHE"] = str(tmp_path / "cache")
    return work, env


def test_the_wheel_holds_every_package_and_the_whole_library(installed):
    _, wheel = installed
    names = set(zipfile.ZipFile(wheel).namelist())
    # every file of the compiler (modules, grammar, parser tables), without caches
    # (shipped_trees/ is made by the build, below; the checkout's own copy may be older)
    package_files = sorted(str(p.relative_to(ROOT)) for p in (ROOT / "compiler").rglob("*")
                           if p.is_file() and "__pycache__" not in p.parts and "shipped_trees" not in p.parts)
    missing = [p for p in package_files if p not in names]
    assert not missing, f"files of compiler/ missing from the wheel: {missing}"
    # the library's parsed trees, made by setup.py's build (compiler/cache/library_trees.py)
    from compiler.cache.library_trees import TREE_SUFFIX, tree_key
    trees = {f"compiler/cache/shipped_trees/{tree_key(p.read_text(encoding='utf-8'))}{TREE_SUFFIX}"
             for p in (ROOT / "components").rglob("*.dyad")}
    assert trees and not trees - names, f"parsed trees missing from the wheel: {sorted(trees - names)[:3]}"
    assert "compiler/syntax/grammar.lark" in names
    library = sorted(str(p.relative_to(ROOT / "components")) for pattern in ("*.dyad", "*.jl")
                     for p in (ROOT / "components").rglob(pattern))
    assert "HydraulicComponents/src/media.jl" in library        # the media's Julia sources
    missing = [p for p in library if f"compiler/components/{p}" not in names]
    assert library and not missing, f"library files missing from the wheel: {missing}"
    assert not any(n.startswith(("tests/", "components/")) for n in names)
    # the C build the runtime calls for a model that reaches a run undecided (runtime/model_code.py)
    [entry_points] = [n for n in names if n.endswith(".dist-info/entry_points.txt")]
    declared = zipfile.ZipFile(wheel).read(entry_points).decode()
    assert "[dyadc.model_code]\nbuild = compiler.cache.c_code:for_a_run\n" in declared


def test_installed_dyadc_simulates_the_excavator_from_an_empty_folder(installed, outside):
    env_dir, _ = installed
    work, env = outside
    dyadc = env_dir / "bin" / "dyadc"
    # the console script runs the fresh environment's interpreter (pip writes a longer launcher
    # when the path is too long for a #! line, hence "within the first lines")
    assert str(env_dir / "bin" / "python") in "\n".join(dyadc.read_text().splitlines()[:3])
    _run([dyadc, "simulate", EXCAVATOR, "--stop", "0.5", "--output", "excavator.csv"], cwd=work, env=env)
    assert sorted(p.name for p in work.iterdir()) == ["excavator.csv", "excavator.csv.json"]   # + sidecar
    with open(work / "excavator.csv", newline="") as handle:
        rows = list(csv.reader(handle))
    final = dict(zip(rows[0], map(float, rows[-1])))
    with open(GOLDEN, newline="") as handle:
        golden_rows = list(csv.reader(handle))
    golden = dict(zip(golden_rows[0], map(float, golden_rows[51])))     # t = 0.5
    assert final["time"] == golden["time"] == 0.5
    for signal in ("boom_joint.phi", "stick_joint.phi", "bucket_joint.phi", "bucket.frame_b.x"):
        assert abs(final[signal] - golden[signal]) < 1e-4, signal       # the dig cycle's tube

    # The same interpreter and path as the run above: everything came from the fresh environment.
    probe = textwrap.dedent(f"""
        import json, sys
        import compiler, compiler.cli
        from compiler.model.library import Library
        from compiler.model.library_path import shipped_library_root
        print(json.dumps({{
            "modules": [compiler.__file__, compiler.cli.__file__],
            "library": str(shipped_library_root()),
            "excavator": Library().find({EXCAVATOR!r}).file.span.file,
            "finders": [repr(f) for f in sys.meta_path]}}))
    """)
    where = json.loads(_run([env_dir / "bin" / "python", "-c", probe], cwd=work, env=env).stdout)
    for path in where["modules"] + [where["library"], where["excavator"]]:
        assert Path(path).resolve().is_relative_to(env_dir.resolve()), path
        assert not Path(path).resolve().is_relative_to(ROOT), path
    assert not any("editable" in finder.lower() for finder in where["finders"])


def test_installed_dyadc_finds_a_user_library_with_L_and_DYADC_PATH(installed, outside, tmp_path):
    env_dir, _ = installed
    work, env = outside
    library = tmp_path / "userlib" / "UserLib"
    library.mkdir(parents=True)
    (library / "Decay.dyad").write_text(
        "component Decay\n  variable x::Real\nrelations\n  initial x = 1\n  der(x) = -x\nend\n")
    dyadc = env_dir / "bin" / "dyadc"
    by_flag = _run([dyadc, "check", "UserLib.Decay", "-L", library.parent], cwd=work, env=env)
    by_variable = _run([dyadc, "check", "UserLib.Decay"], cwd=work,
                       env={**env, "DYADC_PATH": str(library.parent)})
    assert "balanced" in by_flag.stdout and "balanced" in by_variable.stdout
    missing = subprocess.run([dyadc, "check", "UserLib.Decay"], cwd=work, env=env,
                             capture_output=True, text=True, timeout=TIMEOUT)
    assert missing.returncode == 1 and "no model `UserLib.Decay`" in missing.stderr
