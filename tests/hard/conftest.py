"""Shared fixtures of the hard-case suite: model paths, the compiled excavator and its default run.

Every test here runs in `make test` (no environment variable gates any of them)."""
from __future__ import annotations

from pathlib import Path

import pytest

from compiler import api, runtime

MODELS = Path(__file__).resolve().parent.parent / "models"
EXCAVATOR = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"


def compile_hard(name: str):
    return api.compile(f"Hard.{name}", lib_dirs=(str(MODELS),))


@pytest.fixture(scope="session")
def excavator():
    """Compiled once, on the code runs take by default (C where a compiler is present); every
    variant below is a runtime parameter override of this compilation."""
    from compiler.cache.native import on_its_code
    compilation = api.compile(EXCAVATOR)
    compilation.model = on_its_code(compilation.model)
    return compilation


@pytest.fixture(scope="session")
def excavator_default(excavator):
    return runtime.simulate(excavator.model, 12.0, points=1201)
