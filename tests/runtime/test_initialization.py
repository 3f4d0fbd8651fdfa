"""Consistent initialization: redundant consistent conditions pass, inconsistent ones are named."""
from __future__ import annotations

import numpy as np
import pytest
import sympy

from tests.runtime import runtime_systems as systems
from compiler import runtime
from compiler.errors import SimulationError
from compiler.lower.to_casadi import lower
from tests.runtime.lowered import simulate_reduced


def test_redundant_but_consistent_conditions_are_accepted():
    system = systems.pendulum_cartesian(0.7, redundant=True)
    assert len(system.initial.residuals) == 6 > len(system.states) + len(system.algebraics)
    model = lower(system)
    point = runtime.consistent_initialization(model, model.parameter_vector({}), 0.0)
    x, y, vx, vy = point.x
    assert (x, y) == pytest.approx((np.sin(0.7), -np.cos(0.7)), abs=1e-12)
    assert (vx, vy) == (pytest.approx(0.0, abs=1e-14), pytest.approx(0.0, abs=1e-14))
    # At rest the tension balances gravity's radial component: lam = g cos(theta0) (L = 1).
    assert point.z[0] == pytest.approx(9.81 * np.cos(0.7), rel=1e-12)


def test_initialization_is_independent_of_equation_units():
    """A residual in Pa next to one in m: the row scaling keeps the check meaningful."""
    model = lower(systems.rc_circuit())
    point = runtime.consistent_initialization(model, model.parameter_vector({"V": 2e7, "R": 1e-3}),
                                              0.0)
    assert point.z[0] == pytest.approx(2e10, rel=1e-12)


def test_inconsistent_conditions_name_the_residuals_that_disagree():
    system = systems.pendulum_cartesian(0.7, redundant=True, y_start=-0.5)
    model = lower(system)
    with pytest.raises(runtime.InitializationFailed) as info:
        runtime.consistent_initialization(model, model.parameter_vector({}), 0.0)
    worst_indices = {index for index, _, _ in info.value.worst}
    # The start values of x and y and the rod constraint cannot all hold.
    assert worst_indices & {1, 2, 5}
    assert "initialization failed" in str(info.value)


def test_inconsistent_initialization_becomes_a_located_dyad_error():
    with pytest.raises(SimulationError) as info:
        simulate_reduced(systems.pendulum_cartesian(0.7, redundant=True, y_start=-0.5), 1.0)
    text = info.value.format()
    assert "initialization failed" in text
    assert "model.dyad:" in text                      # spans of the equations that disagree
    assert info.value.time_reached == 0.0


def test_unsolvable_initial_equation_is_reported():
    system = systems.pendulum_angle()
    system.initial.residuals = [sympy.Symbol("theta") ** 2 + 1, sympy.Symbol("omega")]
    with pytest.raises(runtime.InitializationFailed) as info:
        runtime.consistent_initialization(lower(system), np.array([9.81, 1.0, 1.0]), 0.0)
    assert info.value.worst[0][0] == 0


def test_guesses_select_the_branch():
    theta = sympy.Symbol("theta")
    system = systems.pendulum_angle()
    system.initial.residuals = [theta**2 - 4, sympy.Symbol("omega")]
    for guess, root in [(1.0, 2.0), (-1.0, -2.0)]:
        system.initial.guesses = {"theta": guess}
        model = lower(system)
        point = runtime.consistent_initialization(model, model.parameter_vector({}), 0.0)
        assert point.x[0] == pytest.approx(root, rel=1e-14)
