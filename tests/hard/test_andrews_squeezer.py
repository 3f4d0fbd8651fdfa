"""Andrews' squeezer written in our language as the Test Set's index-3 DAE with Lagrange
multipliers (tests/models/Hard/AndrewsSqueezer.dyad), against the Test Set reference at t = 0.03.
"""
from __future__ import annotations

import numpy as np
import pytest

from compiler import api
from tests.hard.conftest import compile_hard
from tests.reference import andrews

RATE_NAMES = ("bep", "thp", "gap", "php", "dep", "omp", "epp")


def relative_errors(computed, reference):
    return np.abs(np.asarray(computed) - reference) / np.abs(reference)


@pytest.fixture(scope="module")
def squeezer():
    compilation = compile_hard("AndrewsSqueezer")
    # rtol 1e-11 is the tightest that starts: at 3e-12 (or atol <= 1e-13) IDAS's own initial
    # completion (calc_ic) fails at t = 0 with IDA_LINESEARCH_FAIL.
    return compilation, api.simulate_compiled(compilation, andrews.T_END, points=31, rtol=1e-11, atol=1e-11)


def test_index_reduction_keeps_the_crank_as_the_only_degree_of_freedom(squeezer):
    compilation, _ = squeezer
    assert compilation.model.state_names == ["beta", "bep"]


def test_angles_match_the_test_set_to_six_significant_digits(squeezer):
    _, res = squeezer
    angles = [res[name][-1] for name in andrews.ANGLE_NAMES]
    # By t = 0.03 the crank has turned 2.5 times (beta = 15.8 rad) and spins at 1140 rad/s.
    # Measured: 1.1e-8 (gamma) at rtol 1e-11.
    assert np.max(relative_errors(angles, andrews.REFERENCE_ANGLES)) < 1e-6


def test_crank_rates_match_the_test_set_to_six_significant_digits(squeezer):
    _, res = squeezer
    rates = [res[name][-1] for name in RATE_NAMES[:2]]
    assert np.max(relative_errors(rates, andrews.REFERENCE_RATES[:2])) < 1e-6     # measured 1.7e-9


@pytest.mark.xfail(strict=False, reason=(
    "the dependent rates (gap, php, dep, omp, epp: dummy derivatives, algebraic in IDAS) reach only "
    "1.25e-6 relative at rtol 1e-11 (6.3e-6 at 1e-10) since the runtime excludes algebraic unknowns "
    "from the error test (IDAS suppress_algebraic); tighter rtol fails at t = 0 (IDA_LINESEARCH_FAIL). "
    "Before that change rtol 1e-10 gave 1.5e-7."))
def test_dependent_rates_match_the_test_set_to_six_significant_digits(squeezer):
    _, res = squeezer
    rates = [res[name][-1] for name in RATE_NAMES[2:]]
    assert np.max(relative_errors(rates, andrews.REFERENCE_RATES[2:])) < 1e-6


def test_multipliers_match_the_reference_state_to_six_significant_digits(squeezer):
    _, res = squeezer
    multipliers = np.array([res[f"lambda[{i}]"][-1] for i in range(1, 7)])
    # The multipliers the exact equations give at the Test Set's own final angles and rates
    # (index-1 solve in tests/reference/andrews.py). The Test Set's printed multipliers differ from
    # these by up to 1.26e-6 (lambda[6]): the 16 printed digits of the rates do not fix the
    # centrifugal terms better than that. Against the printed ones we allow that much more.
    _, implied = andrews.accelerations_and_multipliers(andrews.REFERENCE_ANGLES, andrews.REFERENCE_RATES)
    assert np.max(relative_errors(multipliers, implied)) < 1e-6           # measured 1.3e-7
    assert np.max(relative_errors(multipliers, andrews.REFERENCE_MULTIPLIERS)) < 2e-6   # measured 1.15e-6


def test_constraints_hold_along_the_whole_run(squeezer):
    _, res = squeezer
    q = np.array([res[name] for name in andrews.ANGLE_NAMES])
    v = np.array([res[name] for name in RATE_NAMES])
    for k in range(len(res.time)):
        assert np.max(np.abs(andrews.constraints(q[:, k]))) < 1e-12
        assert np.max(np.abs(andrews.constraint_jacobian(q[:, k]) @ v[:, k])) < 1e-8
