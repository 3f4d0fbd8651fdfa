"""ElectricalComponents' controlled ideal switches (Analog.Ideal.ControlledIdeal*Switch) by nodal
analysis while their control voltage, sin(2 pi t), is above and below the level 0.5 V; model
tests/models/Stdlib/ControlledSwitches.dyad."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled

RON = GOFF = 1e-5


@pytest.fixture(scope="module")
def run():
    return Compiled().run("ControlledSwitches", 1.0, points=601)


@pytest.fixture(scope="module")
def sides(run):
    """(above, below): samples at least 0.01 V clear of the level (crossed at t = 1/12, 5/12)."""
    control = np.sin(2 * np.pi * run.time)
    np.testing.assert_allclose(run["control.v"], control, atol=1e-12)
    return control > 0.51, control < 0.49


def closed_current(r):
    return 10 / (r + RON)


def open_current(r):
    return 10 / (r + 1 / GOFF)


def test_both_sides_of_the_level_are_sampled(sides):
    above, below = sides
    assert np.count_nonzero(above) > 50 and np.count_nonzero(below) > 50


def test_opening_switch_opens_above_the_level(run, sides):
    above, below = sides
    np.testing.assert_allclose(run["opener.i"][above], open_current(10), rtol=1e-10)
    np.testing.assert_allclose(run["opener.i"][below], closed_current(10), rtol=1e-10)
    np.testing.assert_allclose(run["opener.control.i"], 0.0, atol=0)


def test_closing_switch_closes_above_the_level(run, sides):
    above, below = sides
    np.testing.assert_allclose(run["closer.i"][above], closed_current(10), rtol=1e-10)
    np.testing.assert_allclose(run["closer.i"][below], open_current(10), rtol=1e-10)


def test_commuting_switch_joins_n2_above_the_level_and_n1_below(run, sides):
    above, below = sides
    np.testing.assert_allclose(run["commuter.i1"][above], open_current(10), rtol=1e-10)
    np.testing.assert_allclose(run["commuter.i2"][above], closed_current(20), rtol=1e-10)
    np.testing.assert_allclose(run["commuter.i1"][below], closed_current(10), rtol=1e-10)
    np.testing.assert_allclose(run["commuter.i2"][below], open_current(20), rtol=1e-10)
    np.testing.assert_allclose(run["commuter.p.i"], run["commuter.i1"] + run["commuter.i2"],
                               rtol=1e-12)


def crossover_outputs(crossed: bool):
    """Potentials of n1, n2 from nodal analysis: 10 V at p1, 5 V at p2, 10 ohm at n1, 20 ohm at
    n2, each input joined to both outputs through Ron (closed) or Goff (open)."""
    g_on, g_off = 1 / RON, GOFF
    g_straight, g_crossed = (g_off, g_on) if crossed else (g_on, g_off)
    # row k: the currents into output k from p1 and p2 equal its load current
    a = np.array([[g_straight + g_crossed + 1 / 10, 0], [0, g_straight + g_crossed + 1 / 20]])
    b = np.array([g_straight * 10 + g_crossed * 5, g_crossed * 10 + g_straight * 5])
    return np.linalg.solve(a, b)


def test_intermediate_switch_crosses_above_the_level_and_goes_straight_below(run, sides):
    for mask, crossed in zip(sides, (True, False)):
        v1, v2 = crossover_outputs(crossed)
        np.testing.assert_allclose(run["crossover.n1.v"][mask], v1, rtol=1e-10)
        np.testing.assert_allclose(run["crossover.n2.v"][mask], v2, rtol=1e-10)
    above, _ = sides
    v1, v2 = crossover_outputs(True)
    # crossed: 5 V drives n1 and 10 V drives n2, through Ron
    np.testing.assert_allclose(run["crossover.i21"][above], (5 - v1) / RON, rtol=1e-6)
    np.testing.assert_allclose(run["crossover.i12"][above], (10 - v2) / RON, rtol=1e-6)
    np.testing.assert_allclose(run["crossover.n1.i"] + run["crossover.n2.i"],
                               -(run["crossover.p1.i"] + run["crossover.p2.i"]), rtol=1e-12)
