"""The car axis problem (Test Set for IVP Solvers, problem CARAXIS; Hairer & Wanner, Solving
ODEs II, sec. VII.1), an index-3 DAE, reduced by hand to an index-1 ODE for scipy.

Two wheels of mass M eps^2 / 2 each (k below) at p = (xl, yl, xr, yr), joined by an axis of
length L; the left wheel hangs on a spring of rest length L0 from the origin, the right one on
an equal spring from a point (xb, yb) that runs over a bumpy road, yb = r sin(omega t), on the
circle of radius L (xb = sqrt(L^2 - yb^2)). Two constraints with multipliers lambda:

    g1 = xl xb + yl yb = 0,   g2 = (xl - xr)^2 + (yl - yr)^2 - L^2 = 0,
    k p'' = F(p, t) + G(p, t)^T lambda,   G = dg/dp.

Differentiating the constraints twice, G p'' + gamma(p, p', t) = 0 with gamma the terms of g''
free of p'', so p'' and lambda solve the linear system [[k I, -G^T], [G, 0]] [p''; lambda] =
[F; -gamma]. Consistent start (the Test Set's): p = (0, 1/2, 1, 1/2), p' = (-1/2, 0, -1/2, 0),
lambda = 0, on t in [0, 3].
"""
from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

L, L0, R, OMEGA, G_ACC, M, EPS = 1.0, 0.5, 0.1, 10.0, 1.0, 10.0, 0.01
K = M * EPS ** 2 / 2
Y0 = np.array([0.0, 0.5, 1.0, 0.5, -0.5, 0.0, -0.5, 0.0])
T_END = 3.0


def road(t):
    """(xb, yb) and their first and second time derivatives."""
    yb, dyb, ddyb = R * np.sin(OMEGA * t), R * OMEGA * np.cos(OMEGA * t), -R * OMEGA ** 2 * np.sin(OMEGA * t)
    xb = np.sqrt(L ** 2 - yb ** 2)
    dxb = -yb * dyb / xb
    ddxb = -(dyb ** 2 + yb * ddyb) / xb - (yb * dyb) ** 2 / xb ** 3
    return (xb, yb), (dxb, dyb), (ddxb, ddyb)


def constraints(t, p):
    (xb, yb), _, _ = road(t)
    xl, yl, xr, yr = p
    return np.array([xl * xb + yl * yb, (xl - xr) ** 2 + (yl - yr) ** 2 - L ** 2])


def constraint_jacobian(t, p):
    (xb, yb), _, _ = road(t)
    xl, yl, xr, yr = p
    return np.array([[xb, yb, 0.0, 0.0], [2 * (xl - xr), 2 * (yl - yr), -2 * (xl - xr), -2 * (yl - yr)]])


def accelerations_and_multipliers(t, p, v):
    """p'' and lambda at (t, p, p') from the index-1 system."""
    (xb, yb), (dxb, dyb), (ddxb, ddyb) = road(t)
    xl, yl, xr, yr = p
    vxl, vyl, vxr, vyr = v
    left, right = np.hypot(xl, yl), np.hypot(xr - xb, yr - yb)
    forces = np.array([(L0 - left) * xl / left, (L0 - left) * yl / left - K * G_ACC,
                       (L0 - right) * (xr - xb) / right, (L0 - right) * (yr - yb) / right - K * G_ACC])
    jacobian = constraint_jacobian(t, p)
    gamma = np.array([2 * (vxl * dxb + vyl * dyb) + xl * ddxb + yl * ddyb, 2 * ((vxl - vxr) ** 2 + (vyl - vyr) ** 2)])
    system = np.zeros((6, 6))
    system[:4, :4] = K * np.eye(4)
    system[:4, 4:] = -jacobian.T
    system[4:, :4] = jacobian
    solution = np.linalg.solve(system, np.concatenate([forces, -gamma]))
    return solution[:4], solution[4:]


def rhs(t, y):
    accelerations, _ = accelerations_and_multipliers(t, y[:4], y[4:])
    return np.concatenate([y[4:], accelerations])


def solve(t_eval=None, method="DOP853", rtol=1e-13, atol=1e-13):
    """solve_ivp of the index-1 formulation from the consistent start over [0, T_END]."""
    return solve_ivp(rhs, (0.0, T_END), Y0, method=method, t_eval=t_eval, rtol=rtol, atol=atol)
