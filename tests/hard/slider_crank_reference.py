"""Hand-derived reduced model of tests/models/Hard/SliderCrank.dyad: one coordinate, the crank angle.

Geometry (slider on y = 0 to the right of the crank pivot, r < l):
    crank tip   P = r (cos th, sin th)
    rod angle   sin psi = -r sin th / l,  cos psi = +sqrt(1 - sin^2 psi)
    slider      x_s = r cos th + l cos psi
Centres of mass: crank a1 (cos th, sin th); rod P + a2 (cos psi, sin psi); slider (x_s, 0).
With T = J(th) th'^2 / 2 and V(th) = g (m1 y1 + m2 y2) (the slider does not rise), Lagrange's
equation is  J th'' + J'(th) th'^2 / 2 + V'(th) = 0. sympy differentiates J and V; nothing here
uses the compiler.
"""
from __future__ import annotations

import numpy as np
import sympy
from scipy.integrate import solve_ivp

G = 9.80665
# The values of SliderCrank.dyad (the model is the source of truth; keep both in step)
PARAMS = dict(r=0.1, l=0.3, a1=0.05, a2=0.15, m1=1.0, I1=1e-3, m2=0.5, I2=4e-3, m3=2.0)


def _reduced_functions(p=PARAMS):
    th = sympy.Symbol("th")
    r, l, a1, a2 = p["r"], p["l"], p["a1"], p["a2"]
    psi = sympy.asin(-r * sympy.sin(th) / l)
    xs = r * sympy.cos(th) + l * sympy.cos(psi)
    c1 = sympy.Matrix([a1 * sympy.cos(th), a1 * sympy.sin(th)])
    c2 = sympy.Matrix([r * sympy.cos(th) + a2 * sympy.cos(psi), r * sympy.sin(th) + a2 * sympy.sin(psi)])
    d = lambda e: sympy.diff(e, th)  # noqa: E731
    J = (p["I1"] + p["m1"] * (d(c1[0]) ** 2 + d(c1[1]) ** 2) + p["I2"] * d(psi) ** 2
         + p["m2"] * (d(c2[0]) ** 2 + d(c2[1]) ** 2) + p["m3"] * d(xs) ** 2)
    V = G * (p["m1"] * c1[1] + p["m2"] * c2[1])
    f = sympy.lambdify
    return f(th, J), f(th, d(J)), f(th, d(V)), f(th, xs), f(th, psi)


def solve(t_eval, theta0, w0, rtol=1e-12, atol=1e-12):
    """Crank angle, rate, slider position and rod angle at t_eval."""
    J, dJ, dV, xs, psi = _reduced_functions()

    def rhs(t, y):
        th, w = y
        return [w, -(0.5 * dJ(th) * w * w + dV(th)) / J(th)]

    t_eval = np.asarray(t_eval, dtype=float)
    sol = solve_ivp(rhs, (t_eval[0], t_eval[-1]), [theta0, w0], method="DOP853", t_eval=t_eval,
                    rtol=rtol, atol=atol)
    th, w = sol.y
    return {"theta": th, "w": w, "x_slider": np.array([xs(v) for v in th]),
            "psi": np.array([psi(v) for v in th])}
