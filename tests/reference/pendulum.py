"""Closed-form planar pendulum released from rest (point mass m on a massless rod of length L).

theta is measured from the downward vertical, positive counter-clockwise, so the bob is at
x = L sin(theta), y = -L cos(theta) with the pivot at the origin and gravity along -y.
Released from rest at theta0 (|theta0| < pi), energy conservation gives with k = sin(theta0/2),
w0 = sqrt(g/L) and the Jacobi elliptic functions of parameter m = k^2:

    sin(theta/2) = k sn(K(m) - w0 t | m)        theta(0) = theta0, theta'(0) = 0
    theta'       = -2 k w0 cn(K(m) - w0 t | m)   (differentiate; cos(theta/2) = dn)
    period       = 4 K(m) / w0

and the rod tension (force on the bob towards the pivot) T = m (L theta'^2 + g cos theta).
"""
from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp
from scipy.special import ellipj, ellipk

G = 9.80665


def period(L=1.0, theta0=0.5, g=G):
    return 4.0 * ellipk(np.sin(theta0 / 2.0) ** 2) / np.sqrt(g / L)


def solution(t, m=1.0, L=1.0, theta0=0.5, g=G):
    """Angle, rate, acceleration, bob position/velocity and rod tension at times t."""
    t = np.asarray(t, dtype=float)
    k = np.sin(theta0 / 2.0)
    w0 = np.sqrt(g / L)
    K = ellipk(k * k)
    sn, cn, dn, _ = ellipj(K - w0 * t, k * k)
    # sign(theta0) carries over through k; arcsin is exact because |k sn| <= |k| < 1
    theta = 2.0 * np.arcsin(k * sn)
    omega = -2.0 * k * w0 * cn
    alpha = -(g / L) * np.sin(theta)
    x, y = L * np.sin(theta), -L * np.cos(theta)
    return {
        "theta": theta, "omega": omega, "alpha": alpha,
        "x": x, "y": y, "vx": L * np.cos(theta) * omega, "vy": L * np.sin(theta) * omega,
        "tension": m * (L * omega ** 2 + g * np.cos(theta)),
    }


def angle_ode(t, state, L=1.0, g=G):
    theta, omega = state
    return [omega, -(g / L) * np.sin(theta)]


def solve_numerically(t_eval, L=1.0, theta0=0.5, g=G, method="DOP853", rtol=1e-12, atol=1e-12,
                      jac=False):
    """solve_ivp of the angle ODE; returns the OdeResult (jac=True passes the exact Jacobian)."""
    t_eval = np.asarray(t_eval, dtype=float)
    options = {}
    if jac:
        options["jac"] = lambda t, s, L, g: [[0.0, 1.0], [-(g / L) * np.cos(s[0]), 0.0]]
    return solve_ivp(angle_ode, (0.0, float(t_eval[-1])), [theta0, 0.0], method=method, t_eval=t_eval,
                     rtol=rtol, atol=atol, args=(L, g), **options)
