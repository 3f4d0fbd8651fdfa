import numpy as np
import pytest

from . import pendulum as pend


@pytest.mark.parametrize("theta0", [0.1, 1.0, 2.5, -1.2])
def test_closed_form_matches_tight_numerical_solution(theta0):
    L, g = 1.3, 9.80665
    t = np.linspace(0.0, 3.0 * pend.period(L, theta0, g), 400)
    exact = pend.solution(t, m=2.0, L=L, theta0=theta0, g=g)
    sol = pend.solve_numerically(t, L=L, theta0=theta0, g=g, rtol=1e-12, atol=1e-12)
    assert sol.success
    np.testing.assert_allclose(sol.y[0], exact["theta"], atol=1e-9)
    np.testing.assert_allclose(sol.y[1], exact["omega"], atol=1e-9 * np.sqrt(g / L))


def test_initial_conditions_and_period():
    out = pend.solution(np.array([0.0]), m=1.0, L=2.0, theta0=0.8)
    assert out["theta"][0] == pytest.approx(0.8, abs=1e-15)
    assert out["omega"][0] == pytest.approx(0.0, abs=1e-15)
    T = pend.period(2.0, 0.8)
    back = pend.solution(np.array([T, T / 2]), m=1.0, L=2.0, theta0=0.8)
    assert back["theta"][0] == pytest.approx(0.8, abs=1e-12)
    assert back["theta"][1] == pytest.approx(-0.8, abs=1e-12)
    # small-amplitude limit: 2 pi sqrt(L/g)
    assert pend.period(2.0, 1e-6) == pytest.approx(2 * np.pi * np.sqrt(2.0 / 9.80665), rel=1e-12)


def test_cartesian_quantities_are_consistent():
    m, L, g, theta0 = 0.7, 1.5, 9.80665, 1.1
    t = np.linspace(0.0, 4.0, 300)
    out = pend.solution(t, m=m, L=L, theta0=theta0, g=g)
    np.testing.assert_allclose(out["x"] ** 2 + out["y"] ** 2, L * L, rtol=1e-14)
    h = 1e-6
    plus, minus = pend.solution(t + h, m, L, theta0, g), pend.solution(t - h, m, L, theta0, g)
    np.testing.assert_allclose((plus["x"] - minus["x"]) / (2 * h), out["vx"], atol=1e-7)
    np.testing.assert_allclose((plus["y"] - minus["y"]) / (2 * h), out["vy"], atol=1e-7)
    np.testing.assert_allclose((plus["omega"] - minus["omega"]) / (2 * h), out["alpha"], atol=1e-6)
    # energy is conserved
    energy = 0.5 * m * (out["vx"] ** 2 + out["vy"] ** 2) + m * g * out["y"]
    np.testing.assert_allclose(energy, -m * g * L * np.cos(theta0), rtol=1e-13)
    # tension from Newton's law along the rod, with the acceleration differentiated numerically:
    # m a = -T r/L + m g_vec  =>  T = (m g_vec - m a) . r / L
    ax = (plus["vx"] - minus["vx"]) / (2 * h)
    ay = (plus["vy"] - minus["vy"]) / (2 * h)
    radial = (m * (0.0 - ax) * out["x"] + m * (-g - ay) * out["y"]) / L
    np.testing.assert_allclose(out["tension"], radial, atol=1e-6 * m * g)
    assert out["tension"][0] == pytest.approx(m * g * np.cos(theta0), rel=1e-14)
