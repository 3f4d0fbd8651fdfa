"""Robertson's chemical kinetics (ROBER), in DAE form and in two ODE forms.

DAE (index 1), as in Hairer & Wanner, Solving ODEs II, sec. IV.1 / VI.1:
    y1' = -k1 y1 + k3 y2 y3
    y2' =  k1 y1 - k3 y2 y3 - k2 y2^2
    0   =  y1 + y2 + y3 - 1
with k1 = 0.04, k2 = 3e7, k3 = 1e4 and y(0) = (1, 0, 0).

Reference solution at t = 1e11 from the Test Set for IVP Solvers (F. Mazzia, C. Magherini et
al., University of Bari; problem ROBER, as shipped e.g. in the R package deTestSet,
function reference("rober")), computed there with rtol = atol = 1e-15 (RADAU5 / ode):
    y1 = 0.2083340149701255e-07, y2 = 0.8333360770334713e-13, y3 = 0.9999999791665050
Published low-accuracy solver outputs at t = 40 (the LSODE and CVODE cvRoberts examples)
agree with each other to about 3-4 digits: y1 = 0.7158, y2 = 9.18e-6, y3 = 0.2842
(a tight Radau solve gives 0.715827069, 9.18553476e-6, 0.284163746).
"""
from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

K1, K2, K3 = 0.04, 3e7, 1e4
Y0 = np.array([1.0, 0.0, 0.0])
REFERENCE_T = 1e11
REFERENCE_Y = np.array([0.2083340149701255e-07, 0.8333360770334713e-13, 0.9999999791665050])
T40_Y_4_DIGITS = np.array([0.7158, 9.18e-6, 0.2842])


def dae_residual(t, y, yp):
    """F(t, y, y') = 0 of the DAE form (first two differential, last algebraic)."""
    y1, y2, y3 = y
    return np.array([
        yp[0] - (-K1 * y1 + K3 * y2 * y3),
        yp[1] - (K1 * y1 - K3 * y2 * y3 - K2 * y2 * y2),
        y1 + y2 + y3 - 1.0,
    ])


def reduced_rhs(t, x):
    """Index-1 DAE with the constraint solved for y3 = 1 - y1 - y2: an ODE in (y1, y2)."""
    y1, y2 = x
    y3 = 1.0 - y1 - y2
    return np.array([-K1 * y1 + K3 * y2 * y3, K1 * y1 - K3 * y2 * y3 - K2 * y2 * y2])


def reduced_jacobian(t, x):
    y1, y2 = x
    y3 = 1.0 - y1 - y2
    # d/dy1 and d/dy2 include the dependence through y3
    return np.array([
        [-K1 - K3 * y2, K3 * y3 - K3 * y2],
        [K1 + K3 * y2, -K3 * y3 + K3 * y2 - 2.0 * K2 * y2],
    ])


def ode_rhs(t, y):
    """Classical 3-component ODE form (y3' = k2 y2^2); conserves y1 + y2 + y3."""
    y1, y2, y3 = y
    return np.array([-K1 * y1 + K3 * y2 * y3, K1 * y1 - K3 * y2 * y3 - K2 * y2 * y2, K2 * y2 * y2])


def ode_jacobian(t, y):
    y1, y2, y3 = y
    return np.array([
        [-K1, K3 * y3, K3 * y2],
        [K1, -K3 * y3 - 2.0 * K2 * y2, -K3 * y2],
        [0.0, 2.0 * K2 * y2, 0.0],
    ])


def solve_reduced(t_eval, method="Radau", rtol=1e-10, atol=1e-14, jac=True):
    """Solve the DAE through its reduced ODE; returns (t, y with 3 rows, OdeResult)."""
    t_eval = np.asarray(t_eval, dtype=float)
    sol = solve_ivp(reduced_rhs, (0.0, float(t_eval[-1])), Y0[:2], method=method, t_eval=t_eval,
                    rtol=rtol, atol=atol, jac=reduced_jacobian if jac else None)
    y = np.vstack([sol.y, 1.0 - sol.y[0] - sol.y[1]])
    return sol.t, y, sol
