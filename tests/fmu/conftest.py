"""FMUs exported once per test session, and a fresh virtual environment with FMPy and not dyadc."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from compiler import api

MODELS = str(Path(__file__).resolve().parent.parent / "models")


@pytest.fixture(scope="session")
def exported(tmp_path_factory):
    """(model name, kind, FMI version, -p values) -> its FMU (exported on first use, once a session)."""
    folder = tmp_path_factory.mktemp("fmus")
    made: dict[str, Path] = {}

    def fmu(model: str, kind: str = "me", fmi: int = 2, **params: float) -> Path:
        key = f"{model} {kind} {fmi}" + "".join(f" {k}={v}" for k, v in sorted(params.items()))
        if key not in made:
            path = folder / f"{model.replace('.', '_')}{len(made)}.fmu"
            made[key] = api.export_fmu(model, path, lib_dirs=[MODELS], params=params or None, kind=kind, fmi=fmi)
        return made[key]
    return fmu


@pytest.fixture(scope="session")
def dyadc_run():
    """dyadc's own run of a model on a time grid, made once a session for each (model, stop, grid,
    tolerance, library folders): the FMI 2.0 and 3.0 tests of a model compare with the same run."""
    made: dict[tuple, object] = {}

    def run(model: str, stop: float, times, tolerance: float = 1e-10, lib_dirs: tuple[str, ...] = (MODELS,)):
        times = np.asarray(times, dtype=float)
        key = (model, stop, times.tobytes(), tolerance, lib_dirs)
        if key not in made:
            made[key] = api.simulate(model, stop, lib_dirs=list(lib_dirs), rtol=tolerance, atol=tolerance,
                                     saveat=times)
        return made[key]
    return run


@pytest.fixture(scope="session")
def fresh_python(tmp_path_factory) -> Path:
    """The python of a new virtual environment holding FMPy (from the package index) and not
    dyadc, made once per session."""
    folder = tmp_path_factory.mktemp("fresh-venv")
    subprocess.run([sys.executable, "-m", "venv", str(folder)], check=True, capture_output=True, timeout=300)
    python = folder / "bin" / "python"
    done = subprocess.run([str(python), "-m", "pip", "install", "--quiet", "--disable-pip-version-check", "fmpy"], capture_output=True,
                          text=True, timeout=600)
    if done.returncode != 0:
        pytest.fail(f"pip could not install fmpy into a fresh environment: {done.stderr[-2000:]}")
    return python
