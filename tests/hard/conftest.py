"""Shared fixtures of the hard-case suite: model paths, the compiled excavator and its default run.

Long variants (minutes) run only with DYADC_HARD_LONG=1; each has a short variant that always runs.
"""
from __future__ import annotations

import os
from pathlib import Path

import pytest

from compiler import api, runtime

MODELS = Path(__file__).resolve().parent.parent / "models"
EXCAVATOR = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"
RUN_LONG = os.environ.get("DYADC_HARD_LONG") == "1"

long_running = pytest.mark.skipif(not RUN_LONG, reason="takes minutes; set DYADC_HARD_LONG=1 to run it")


def compile_hard(name: str):
    return api.compile(f"Hard.{name}", lib_dirs=(str(MODELS),))


@pytest.fixture(scope="session")
def excavator():
    """Compiled once; every variant below is a runtime parameter override of this compilation."""
    return api.compile(EXCAVATOR)


@pytest.fixture(scope="session")
def excavator_default(excavator):
    return runtime.simulate(excavator.model, 12.0, points=1201)
