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


def _natural_spline_of_squares():
    from scipy.interpolate import CubicSpline
    return CubicSpline(KNOTS, KNOTS ** 2, bc_type="natural", extrapolate=True)


def test_extrapolation_constant_holds_the_end_samples(run):
    u = 2 * run.time - 1
    np.testing.assert_allclose(run["chord_held.y"], np.interp(u, KNOTS, KNOTS ** 2), atol=1e-9)
    spline = _natural_spline_of_squares()
    np.testing.assert_allclose(run["spline_held.y"], spline(np.clip(u, 0, 2)), atol=1e-9)


def test_extrapolation_extension_continues_the_end_cubics(run):
    u = 2 * run.time - 1
    np.testing.assert_allclose(run["spline_extended.y"], _natural_spline_of_squares()(u), atol=1e-9)


def test_extrapolation_linear_follows_the_end_tangents(run):
    u = 2 * run.time - 1
    spline = _natural_spline_of_squares()
    slope = spline.derivative()
    expected = np.where(u < 0, slope(0.0) * u, np.where(u > 2, 4 + slope(2.0) * (u - 2), spline(u)))
    np.testing.assert_allclose(run["spline_tangent.y"], expected, atol=1e-9)
    assert abs(run["spline_tangent.y"][-1] - run["spline_extended.y"][-1]) > 0.1   # not the cubic
