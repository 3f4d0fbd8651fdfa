"""Andrews' squeezer (tests/models/Hard/AndrewsSqueezer.dyad) at rtol 1e-11 and 1e-12: it runs
over the whole span t = 0 .. 0.03 and gains digits over rtol 1e-10 (issue 16, item 4).

The reference is computed here, independently of dyadc: scipy's DOP853 on the hand-reduced
index-1 ODE of tests/reference/andrews.py at rtol = atol = 1e-13 (its runs at 1e-13 and 1e-14
agree to 1e-12 in the angles and 6e-11 in the rates). The Test Set's printed reference (PSIDE on
a Cray C90) is itself 2.7e-10 off in the angles and up to 5.1e-8 in the dependent rates from it,
so beyond about 7 digits in the rates it cannot tell a better run from a worse one.

Why it failed before (docs/numerics.md): the consistent start solved the equations only to the
initialization's stopping test (der(epp)'s Newton correction was 45 IDAS weights at 1e-12: the
error test failed at t = 0), and the dependent accelerations' absolute tolerance sat below the
round-off of their equations (runtime/idas.py, DUMMY_ATOL_FLOOR: IDAS's Newton test failed on
round-off until the step collapsed).
"""
from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

from compiler import api
from compiler.runtime.idas import DUMMY_ATOL_FLOOR, error_controlled, integrator_options
from compiler.runtime.initialization import consistent_initialization
from tests.hard.conftest import compile_hard
from tests.reference import andrews

RATE_NAMES = ("bep", "thp", "gap", "php", "dep", "omp", "epp")
ACCELERATION_NAMES = ("a_beta", "a_Theta", "a_gamma", "a_Phi", "a_delta", "a_Omega", "a_epsilon")
MULTIPLIER_NAMES = tuple(f"lambda[{i}]" for i in range(1, 7))


@pytest.fixture(scope="module")
def squeezer():
    return compile_hard("AndrewsSqueezerAccelerations")


@pytest.fixture(scope="module")
def reference():
    """The state at t = 0.03 by DOP853 at rtol 1e-13, with the accelerations and multipliers the
    exact equations give there: {group: (names, values)}."""
    solution = andrews.solve(np.array([0.0, andrews.T_END]), method="DOP853", rtol=1e-13, atol=1e-13)
    assert solution.success
    angles, rates = solution.y[:7, -1], solution.y[7:14, -1]
    accelerations, multipliers = andrews.accelerations_and_multipliers(angles, rates)
    return {"angles": (andrews.ANGLE_NAMES, angles), "rates": (RATE_NAMES, rates),
            "accelerations": (ACCELERATION_NAMES, accelerations),
            "multipliers": (MULTIPLIER_NAMES, multipliers)}


@pytest.fixture(scope="module", params=["native", "casadi"])
def runs(request, squeezer):
    """The runs at rtol 1e-10, 1e-11 and 1e-12 on one integrator, by rtol (and "integrator")."""
    found = {rtol: api.simulate_compiled(squeezer, andrews.T_END, points=31, rtol=rtol, atol=rtol,
                                         integrator=request.param) for rtol in (1e-10, 1e-11, 1e-12)}
    assert {r.stats["integrator"] for r in found.values()} == {request.param}
    return {**found, "integrator": request.param}


def worst_relative_error(result, names, values) -> float:
    computed = np.array([result[name][-1] for name in names])
    return float(np.max(np.abs(computed - values) / np.abs(values)))


@pytest.mark.parametrize("rtol", [1e-11, 1e-12])
def test_runs_over_the_whole_span_on_the_constraints(runs, rtol):
    result = runs[rtol]
    assert result.time[-1] == pytest.approx(andrews.T_END, abs=0)
    for k in range(len(result.time)):
        q = np.array([result[name][k] for name in andrews.ANGLE_NAMES])
        v = np.array([result[name][k] for name in RATE_NAMES])
        assert np.max(np.abs(andrews.constraints(q))) < 1e-15            # measured 2.8e-17
        assert np.max(np.abs(andrews.constraint_jacobian(q) @ v)) < 1e-12  # measured 6.7e-15


# Measured worst relative errors per group (angles, rates, accelerations, multipliers), CasADi's
# IDAS: 1e-10: 2.0e-10, 2.2e-8, 3.4e-8, 2.5e-9; 1e-11: 1.8e-11, 1.9e-9, 2.8e-9, 1.6e-10;
# 1e-12: 6.8e-12, 8.3e-10, 1.3e-9, 8.3e-11. The native driver: 1e-10: 5.5e-11, 6.1e-9, 9.2e-9,
# 4.2e-10; 1e-11: 1.6e-10, 1.8e-8, 2.7e-8, 1.8e-9; 1e-12: 3.0e-11, 3.4e-9, 5.2e-9, 3.4e-10. The
# bounds are about 4x those. At t = 0.03 alone these scatter: the largest error over the 31 output
# times falls 50x from 1e-10 to 1e-12 on CasADi's IDAS and 20x on the native driver
# (docs/numerics.md, "The native IDAS driver": an open gap).
BOUNDS = {"casadi": {1e-11: {"angles": 8e-11, "rates": 8e-9, "accelerations": 1.2e-8, "multipliers": 6e-10},
                     1e-12: {"angles": 3e-11, "rates": 4e-9, "accelerations": 5e-9, "multipliers": 4e-10}},
          "native": {1e-11: {"angles": 6e-10, "rates": 7e-8, "accelerations": 1.1e-7, "multipliers": 7e-9},
                     1e-12: {"angles": 1.2e-10, "rates": 1.4e-8, "accelerations": 2e-8, "multipliers": 1.4e-9}}}


@pytest.mark.parametrize("rtol", [1e-11, 1e-12])
@pytest.mark.parametrize("group", ["angles", "rates", "accelerations", "multipliers"])
def test_every_group_matches_the_independent_reference(runs, reference, rtol, group):
    names, values = reference[group]
    assert worst_relative_error(runs[rtol], names, values) < BOUNDS[runs["integrator"]][rtol][group]


# on CasADi's IDAS only: the native driver gains 1.2-1.8x at t = 0.03 (docs/numerics.md, an open gap)
@pytest.mark.parametrize("runs", ["casadi"], indirect=True)
@pytest.mark.parametrize("group", ["angles", "rates", "accelerations", "multipliers"])
def test_rtol_1e12_gains_a_digit_over_1e10_in_every_group(runs, reference, group):
    names, values = reference[group]
    coarse = worst_relative_error(runs[1e-10], names, values)
    fine = worst_relative_error(runs[1e-12], names, values)
    assert fine < coarse / 10          # measured 26-30x


def test_agrees_with_the_test_set_within_the_test_sets_own_accuracy(runs):
    result = runs[1e-12]
    # DOP853's state lies 2.7e-10 (angles) and 5.1e-8 (rates) from the Test Set's printed one;
    # measured 2.8e-10 and 5.2e-8
    assert worst_relative_error(result, andrews.ANGLE_NAMES, andrews.REFERENCE_ANGLES) < 1e-9
    assert worst_relative_error(result, RATE_NAMES, andrews.REFERENCE_RATES) < 1e-7


def test_the_start_is_consistent_to_the_tightest_tolerance(squeezer):
    """The Newton correction the algebraic equations still ask for at the consistent start is a
    small fraction of IDAS's weights at rtol = atol = 1e-12 (measured 0.016 RMS, 0.07 at most;
    before the start was polished: 10 RMS and 45 in der(epp))."""
    model = squeezer.model
    p = model.parameter_vector({})
    start = consistent_initialization(model, p, 0.0)
    residual, jacobian = model.algebraic_newton()(start.x, start.z, p, 0.0)
    correction = np.linalg.solve(np.asarray(ca.densify(jacobian), dtype=float),
                                 -np.asarray(residual, dtype=float).reshape(-1))
    weights = 1e-12 * np.abs(start.z) + 1e-12
    assert np.max(np.abs(correction) / weights) < 0.5


def test_dummy_states_keep_a_tolerance_above_round_off(squeezer):
    model = squeezer.model
    names = model.state_names + model.algebraic_names
    controlled = error_controlled(model)
    assert {"der(dep)", "der(epp)", "gamma", "der(gamma)"} <= controlled

    def tolerances(rtol, atol):
        return dict(zip(names, integrator_options(model, rtol, atol, 1000, None)["abstolv"]))
    tight = tolerances(1e-12, 1e-12)
    assert tight["beta"] == tight["bep"] == 1e-12                    # the user's, on the states
    assert all(tight[name] == DUMMY_ATOL_FLOOR for name in controlled)
    loose = tolerances(1e-6, 1e-6)
    assert all(loose[name] == 1e-6 for name in controlled)           # looser ones: as given
    given = tolerances(1e-12, {"*": 1e-12, "der(dep)": 1e-13})
    assert given["der(dep)"] == 1e-13                                 # asked for by name: kept
