"""BlockComponents' table blocks (Tables.Interpolation, Tables.ScalarInterpolation) on a clock,
against the chords and steps of samples of u^2 at 0, 0.5, ..., 2 (model
tests/models/Stdlib/TableBlocks.dyad, file tests/models/Stdlib/squares.csv)."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled

KNOTS = np.array([0, 0.5, 1, 1.5, 2])


@pytest.fixture(scope="module")
def run():
    return Compiled().run("TableBlocks", 2.0, points=401)


def test_linear_interpolation_of_a_dataset_and_of_a_file(run):
    chords = np.interp(run.time, KNOTS, KNOTS ** 2)
    np.testing.assert_allclose(run["chord.y"], chords, atol=1e-9)
    np.testing.assert_allclose(run["scalar.y"], chords, atol=1e-9)


def test_constant_interpolation_holds_the_last_sample(run):
    t = run.time
    inside = np.abs(t / 0.5 - np.round(t / 0.5)) > 1e-6          # away from the knots
    held = KNOTS[np.minimum((t / 0.5).astype(int), 4)] ** 2
    np.testing.assert_allclose(run["hold.y"][inside], held[inside], atol=0)
