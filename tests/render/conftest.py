"""Shared compilations: compiling the excavator costs seconds, so each is built once per session."""
from __future__ import annotations

from pathlib import Path

import pytest

from compiler import api

MODELS = Path(__file__).resolve().parent.parent / "models"
EXCAVATOR = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"


@pytest.fixture(scope="session")
def excavator():
    return api.compile(EXCAVATOR)


@pytest.fixture(scope="session")
def excavator_short_result(excavator):
    """The first second of the dig cycle: the arm moves, the tip has not reached the soil yet."""
    return api.simulate_compiled(excavator, 1.0, points=11)


@pytest.fixture(scope="session")
def pendulum():
    return api.compile("ComponentTests.Pendulum", [str(MODELS)])
