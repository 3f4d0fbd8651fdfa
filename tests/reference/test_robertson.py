import numpy as np
import pytest
from scipy.integrate import solve_ivp

from . import robertson as rob


@pytest.fixture(scope="module")
def tight_reduced_solution():
    return rob.solve_reduced([40.0, rob.REFERENCE_T], method="Radau", rtol=1e-10, atol=1e-20)


def test_reduced_dae_reproduces_test_set_reference_at_1e11(tight_reduced_solution):
    _, y, sol = tight_reduced_solution
    assert sol.success
    # measured agreement: ~4e-13 relative in every component
    np.testing.assert_allclose(y[:, -1], rob.REFERENCE_Y, rtol=1e-9, atol=0)


def test_reduced_dae_agrees_with_published_t40_values(tight_reduced_solution):
    _, y, _ = tight_reduced_solution
    np.testing.assert_allclose(y[:, 0], rob.T40_Y_4_DIGITS, rtol=1e-3)


def test_solution_satisfies_dae_residual(tight_reduced_solution):
    _, y, _ = tight_reduced_solution
    for col in range(y.shape[1]):
        yp = np.append(rob.reduced_rhs(0.0, y[:2, col]), 0.0)
        residual = rob.dae_residual(0.0, y[:, col], yp)
        np.testing.assert_allclose(residual, 0.0, atol=1e-15)


def test_ode_form_conserves_mass_and_matches_reduced_form():
    t_eval = np.array([0.4, 40.0, 4e5])
    sol = solve_ivp(rob.ode_rhs, (0, t_eval[-1]), rob.Y0, method="BDF", t_eval=t_eval, rtol=1e-9,
                    atol=1e-16, jac=rob.ode_jacobian)
    assert sol.success
    np.testing.assert_allclose(sol.y.sum(axis=0), 1.0, atol=1e-13)
    _, y_red, _ = rob.solve_reduced(t_eval, method="BDF", rtol=1e-9, atol=1e-16)
    np.testing.assert_allclose(sol.y, y_red, rtol=1e-6, atol=1e-14)


@pytest.mark.parametrize("jac_fun, rhs_fun, n", [(rob.ode_jacobian, rob.ode_rhs, 3),
                                                 (rob.reduced_jacobian, rob.reduced_rhs, 2)])
def test_analytic_jacobians_match_finite_differences(jac_fun, rhs_fun, n):
    y = np.array([0.7, 2e-5, 0.3 - 2e-5])[:n]
    J = jac_fun(0.0, y)
    for j in range(n):
        h = 1e-7 * max(abs(y[j]), 1e-6)
        e = np.zeros(n)
        e[j] = h
        column = (rhs_fun(0.0, y + e) - rhs_fun(0.0, y - e)) / (2 * h)
        np.testing.assert_allclose(J[:, j], column, rtol=1e-6, atol=1e-9 * np.abs(J).max())
