"""`extrapolation_type` Periodic and Reflective (compiler/model/interpolation.py): the table read
back exact at its knots and repeated or mirrored beyond them, as Dyad's ExtrapolationType documents
(A(x + T) = A(x); A(c + d) = A(c - d) at c = first + k T), and each period boundary an event of the
run: a time event where the table is indexed by time, a located state event where it is indexed by
a state (model tests/models/Stdlib/RepeatingTables.dyad)."""
from __future__ import annotations

import numpy as np
import pytest

from compiler.model.interpolation import cubic_spline, extrapolated, linear
from tests.library.stdlib_support import Compiled

KNOTS = [0.0, 0.5, 1.0, 1.5, 2.0]
SQUARES = [k * k for k in KNOTS]


def _reflected(u, first=0.0, span=2.0):
    k = np.floor((u - first) / span)
    offset = u - first - k * span
    return np.where(k % 2 == 0, first + offset, first + span - offset)


def test_periodic_chord_repeats_the_samples_with_the_span_as_period():
    table = extrapolated(linear(SQUARES, KNOTS, "squares"), 0.0, 2.0, "Periodic")
    u = np.linspace(-3, 7, 81)
    expected = np.interp(np.mod(u, 2.0), KNOTS, SQUARES)
    np.testing.assert_allclose([table.value(x) for x in u], expected, atol=1e-12)
    assert [table.value(k + 4.0) for k in KNOTS[:-1]] == SQUARES[:-1]       # knots, shifted


def test_reflective_spline_mirrors_at_every_multiple_of_the_span():
    from scipy.interpolate import CubicSpline
    table = extrapolated(cubic_spline(SQUARES, KNOTS, "squares"), 0.0, 2.0, "Reflective")
    spline = CubicSpline(KNOTS, SQUARES, bc_type="natural")
    u = np.linspace(-3, 7, 81)
    np.testing.assert_allclose([table.value(x) for x in u], spline(_reflected(u)), atol=1e-12)
    assert table.value(2.5) == table.value(1.5) and table.value(-0.5) == table.value(0.5)


def test_derivative_of_a_reflective_table_changes_sign_on_mirrored_periods():
    slope = extrapolated(linear(SQUARES, KNOTS, "squares"), 0.0, 2.0, "Reflective").derivative()
    assert slope.value(1.75) == pytest.approx(3.5)       # d/du of the chord 2.25 -> 4
    assert slope.value(2.25) == pytest.approx(-3.5)      # mirrored: the same chord, read backwards
    assert slope.value(4.25) == pytest.approx(0.5)       # two spans on: the chord 0 -> 0.25 again
    assert slope.value(-0.25) == pytest.approx(-0.5)


@pytest.fixture(scope="module")
def compiled():
    rig = Compiled()
    return rig, rig.run("RepeatingTables", 3.5, points=15)


def _saw_integral(x):
    return np.floor(x) / 2 + (x - np.floor(x)) ** 2 / 2


def test_time_indexed_tables_are_the_sawtooth_and_the_triangle(compiled):
    _, run = compiled
    t = run.time
    np.testing.assert_allclose(run["saw.y"], t - np.floor(t), atol=1e-12)
    np.testing.assert_allclose(run["wave.y"], _reflected(t, 0.0, 1.0), atol=1e-12)
    np.testing.assert_allclose(run["saw_area"], _saw_integral(t), atol=1e-7)
    k, s = np.floor(t), t - np.floor(t)
    np.testing.assert_allclose(run["wave_area"],
                               k / 2 + np.where(k % 2 == 0, s ** 2 / 2, s - s ** 2 / 2), atol=1e-7)


def test_a_time_indexed_period_boundary_is_a_time_event(compiled):
    rig, _ = compiled
    model = rig._cache["RepeatingTables"].model
    offset, period = model.time_events(model.parameter_vector())
    assert (float(offset), float(period)) == (0.0, 1.0)
    assert model.time_event_labels == ["saw.interpolator repeats"]


def test_a_state_indexed_period_boundary_is_a_located_state_event(compiled):
    _, run = compiled
    times = [event["time"] for event in run.events if event["event"] == "state_saw.interpolator repeats"]
    np.testing.assert_allclose(times, [0.75, 1.75, 2.75], atol=1e-9)
    x = 0.25 + run.time
    away = np.abs(x - np.round(x)) > 1e-6         # at a jump x itself is a rounding away from it
    np.testing.assert_allclose(run["state_saw.y"][away], (x - np.floor(x))[away], atol=1e-9)
    np.testing.assert_allclose(run["state_saw_area"], _saw_integral(x) - _saw_integral(0.25),
                               atol=1e-7)


@pytest.mark.parametrize("how", ["Periodic", "Reflective"])
def test_samples_not_starting_at_zero_repeat_from_their_first_sample(how):
    times, values = [1.0, 2.0, 4.0], [5.0, 7.0, 3.0]          # span 3, starting at 1
    table = extrapolated(linear(values, times, "offset"), 1.0, 4.0, how)
    u = np.linspace(-8, 13, 85)
    inner = np.mod(u - 1.0, 3.0) + 1.0 if how == "Periodic" else _reflected(u, 1.0, 3.0)
    np.testing.assert_allclose([table.value(x) for x in u], np.interp(inner, times, values),
                               atol=1e-12)
