"""A closed-loop mechanism through its singular configurations: a slider-crank
(tests/models/Hard/SliderCrank.dyad) started 1e-4 rad past its outer dead centre.

The crank (0.1 m) swings under gravity from 8 rad/s: it passes the outer dead centre (crank
angle 0) repeatedly and goes beyond the inner one (-pi) and back. At a dead centre the slider
position is stationary in the crank angle; at +-pi/2 the rod angle is. The three revolute angles
carry the same state priority, so the compiler's choice decides whether the states degenerate.
Checked against the hand-derived one-coordinate Lagrange model (slider_crank_reference.py).
Requirement: correct results, or a clear stop naming the ill-conditioned constraint and the time.
"""
from __future__ import annotations

import numpy as np
import pytest

from compiler import api
from tests.hard import slider_crank_reference as reference
from tests.hard.conftest import compile_hard

THETA0, W0 = 1e-4, 8.0
R, L = reference.PARAMS["r"], reference.PARAMS["l"]


def check_against_reference(res, scale=1.0):
    """Bounds for a run at rtol 1e-10; `scale` widens them for looser tolerances (error ~ rtol)."""
    exact = reference.solve(res.time, THETA0, W0)
    np.testing.assert_allclose(res["crank_joint.phi"], exact["theta"], atol=1e-6 * scale)
    np.testing.assert_allclose(res["crank_joint.w"], exact["w"], atol=1e-5 * scale)
    np.testing.assert_allclose(res["slider.r[1]"], exact["x_slider"], atol=1e-7 * scale)
    np.testing.assert_allclose(res["rod.frame_a.phi"], exact["psi"], atol=1e-6 * scale)


@pytest.fixture(scope="module")
def equal_priorities():
    return compile_hard("SliderCrank")


@pytest.fixture(scope="module")
def crank_states():
    compilation = compile_hard("SliderCrankCrankStates")
    return compilation, api.simulate_compiled(compilation, 2.0, points=2001, rtol=1e-10, atol=1e-10)


def test_with_the_crank_as_state_it_runs_through_both_dead_centres(crank_states):
    compilation, res = crank_states
    assert compilation.model.state_names == ["crank_joint.phi", "crank_joint.w"]
    theta = res["crank_joint.phi"]
    assert res.time[-1] == 2.0
    assert np.count_nonzero(np.diff(np.sign(theta)) != 0) >= 3          # outer dead centre (0)
    assert theta.min() < -np.pi                                         # past the inner one (-pi)
    # The slider turns at r + l (outer dead centre) and l - r (inner)
    assert res["slider.r[1]"].max() == pytest.approx(R + L, abs=1e-6)
    assert res["slider.r[1]"].min() == pytest.approx(L - R, abs=1e-4)


def test_with_the_crank_as_state_it_matches_the_hand_derived_reduced_model(crank_states):
    _, res = crank_states
    # Measured at rtol 1e-10: 4.9e-8 rad, 6.6e-7 rad/s, 3.1e-9 m
    check_against_reference(res)


def test_with_the_crank_as_state_the_closure_and_guide_constraints_hold(crank_states):
    _, res = crank_states
    tip = np.array([res["crank.frame_b.x"], res["crank.frame_b.y"]])
    slider = np.array([res["slider.r[1]"], res["slider.r[2]"]])
    np.testing.assert_allclose(np.hypot(*(slider - tip)), L, atol=1e-9)
    np.testing.assert_allclose(res["slider.r[2]"], 0.0, atol=1e-12)
    np.testing.assert_allclose(res["slider.phi"], 0.0, atol=1e-12)


@pytest.mark.parametrize("rtol", [1e-9, 1e-10])
def test_equal_priorities_start_from_the_pivoted_state_set_and_run_through_the_dead_centres(
        equal_priorities, rtol):
    # The requirement allows a clear stop naming the constraint, but what happens (on every
    # machine) is a full run that matches the hand-derived model. The compiler pivots on the
    # level Jacobian at the start point, an unknown without a value counted as 0 (2026-11-28,
    # issue 25): it starts from rod_joint, the set the pivot monitor used to switch to at
    # t = 1e-4 when the start choice fell back to structure and took slider_joint, which
    # degenerates there. Nothing needs a switch during the run.
    assert equal_priorities.dynamic
    assert equal_priorities.model.state_names == ["rod_joint.phi", "rod_joint.w"]
    res = api.simulate_compiled(equal_priorities, 2.0, points=2001, rtol=rtol, atol=rtol)
    assert res.time[-1] == 2.0
    check_against_reference(res, scale=rtol / 1e-10)
    assert res.stats["state_switches"] == []
