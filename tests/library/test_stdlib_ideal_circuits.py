"""ElectricalComponents' ideal op-amps, branches, change-over and cross-over switches and the
coupled-inductor transformer against closed forms; model tests/models/Stdlib/IdealCircuits.dyad."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled

RON, GOFF = 0.01, 0.001


@pytest.fixture(scope="module")
def run():
    return Compiled().run("IdealCircuits", 2.0, points=201)


def test_ideal_op_amps_give_the_textbook_gains(run):
    np.testing.assert_allclose(run["amp1.out.v"], -3000 / 1000 * 1.5, rtol=1e-12)
    np.testing.assert_allclose(run["amp1.in_n.v"], 0, atol=1e-12)
    np.testing.assert_allclose(run["amp2.p2.v"], (1 + 4000 / 1000) * 0.5, rtol=1e-12)
    np.testing.assert_allclose(run["amp2.i1"], 0, atol=0)


def test_idle_carries_no_current_and_short_no_voltage(run):
    np.testing.assert_allclose(run["idle.i"], 0, atol=0)
    np.testing.assert_allclose(run["idle.v"], 6, rtol=1e-12)
    np.testing.assert_allclose(run["short.v"], 0, atol=0)
    np.testing.assert_allclose(run["short.i"], 2, rtol=1e-12)


def _branch(v, r, closed):
    """Current of a source v through a switch branch (Ron closed, Goff open) in series with r."""
    return v / (RON + r) if closed else v * GOFF / (1 + GOFF * r)


def test_commuting_switch_moves_the_supply_from_n1_to_n2(run):
    t = run.time
    before, after = t < 0.99, t > 1.01
    for name, r, closed_before in (("r_n1", 5, True), ("r_n2", 20, False)):
        np.testing.assert_allclose(run[f"{name}.i"][before], _branch(10, r, closed_before), rtol=1e-10)
        np.testing.assert_allclose(run[f"{name}.i"][after], _branch(10, r, not closed_before), rtol=1e-10)
    np.testing.assert_allclose(run["commuter.p.i"], run["r_n1.i"] + run["r_n2.i"], rtol=1e-12)


def _crossover(crossed):
    """Node voltages of n1 (load 5) and n2 (load 20) fed from p1 = 10 V and p2 = 4 V: nodal analysis."""
    g_on, g_off = 1 / RON, GOFF
    g11, g22 = (g_off, g_off) if crossed else (g_on, g_on)      # straight branches
    g12, g21 = (g_on, g_on) if crossed else (g_off, g_off)      # crossed branches
    a = np.array([[g11 + g21 + 1 / 5, 0], [0, g12 + g22 + 1 / 20]])
    b = np.array([10 * g11 + 4 * g21, 10 * g12 + 4 * g22])
    return np.linalg.solve(a, b)


def test_intermediate_switch_crosses_the_connections(run):
    t = run.time
    for mask, crossed in ((t < 0.99, False), (t > 1.01, True)):
        v1, v2 = _crossover(crossed)
        np.testing.assert_allclose(run["r_x1.v"][mask], v1, rtol=1e-10)
        np.testing.assert_allclose(run["r_x2.v"][mask], v2, rtol=1e-10)
    # every pin current is the sum of its branches: what enters at p1, p2 leaves at n1, n2
    np.testing.assert_allclose(run["crossover.p1.i"] + run["crossover.p2.i"],
                               -(run["crossover.n1.i"] + run["crossover.n2.i"]), rtol=1e-12)


def test_transformer_with_shorted_secondary_ramps_through_the_leakage_inductance(run):
    t = run.time
    i1 = 2 * t / (1 - 0.5 ** 2 / 2)
    np.testing.assert_allclose(run["transformer.i1"], i1, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(run["transformer.i2"], -0.5 / 2 * i1, rtol=1e-8, atol=1e-12)
