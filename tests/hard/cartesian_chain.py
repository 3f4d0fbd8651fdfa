"""A chain of n point masses on massless rods, hanging from the origin: written out as plain
Cartesian equations for dyadc (one multiplier per rod, index 3), and as the minimal-coordinate
ODE in the rod angles (Lagrange's equations) for an independent reference.

Body i sits at p_i = p_(i-1) + L (sin th_i, -cos th_i), p_0 = 0. With c_jk = m (n - max(j, k) + 1)
and c_j = c_jj, the angles obey
    sum_k c_jk L^2 cos(th_j - th_k) th_k'' = -sum_k c_jk L^2 sin(th_j - th_k) th_k'^2 - g L c_j sin th_j.
"""
from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp


def dyad_source(n: int, angles) -> str:
    """The chain as a Dyad component `CartesianChain<n>` released at rest at the given rod angles
    (from the downward vertical): the horizontal positions and velocities are initial equations,
    the heights come from their guesses (the lower roots)."""
    xs, ys = positions(np.asarray(angles, dtype=float), 1.0)
    lines = [f"component CartesianChain{n}",
             "  parameter L::Real = 1.0", "  parameter m::Real = 1.0", "  parameter g::Real = 9.81"]
    for i in range(1, n + 1):
        lines += [f"  variable x{i}::Real", f"  variable y{i}::Real(guess = {ys[i - 1]:.6f})",
                  f"  variable vx{i}::Real", f"  variable vy{i}::Real", f"  variable lambda{i}::Real(guess = 10)"]
    lines.append("relations")
    for i in range(1, n + 1):
        lines += [f"  initial x{i} = L * {xs[i - 1]:.17g}", f"  initial vx{i} = 0",
                  f"  der(x{i}) = vx{i}", f"  der(y{i}) = vy{i}"]
        px, py = ("0", "0") if i == 1 else (f"x{i - 1}", f"y{i - 1}")
        # rod i pulls body i towards body i - 1; rod i + 1 pulls it towards body i + 1
        fx = f"-lambda{i} * (x{i} - {px})"
        fy = f"-lambda{i} * (y{i} - {py})"
        if i < n:
            fx += f" + lambda{i + 1} * (x{i + 1} - x{i})"
            fy += f" + lambda{i + 1} * (y{i + 1} - y{i})"
        lines += [f"  m * der(vx{i}) = {fx}", f"  m * der(vy{i}) = {fy} - m * g",
                  f"  (x{i} - {px}) ^ 2 + (y{i} - {py}) ^ 2 = L ^ 2"]
    lines.append("end")
    return "\n".join(lines) + "\n"


def positions(angles: np.ndarray, L: float):
    return L * np.cumsum(np.sin(angles), axis=0), -L * np.cumsum(np.cos(angles), axis=0)


def angle_rhs(t, state, n: int, m: float = 1.0, L: float = 1.0, g: float = 9.81):
    th, w = state[:n], state[n:]
    index = np.arange(n)
    c = m * (n - np.maximum.outer(index, index))
    diff = th[:, None] - th[None, :]
    mass = c * L ** 2 * np.cos(diff)
    force = -(c * L ** 2 * np.sin(diff)) @ (w ** 2) - g * L * np.diag(c) * np.sin(th)
    return np.concatenate([w, np.linalg.solve(mass, force)])


def reference(times, angles, m: float = 1.0, L: float = 1.0, g: float = 9.81) -> dict[str, np.ndarray]:
    """Positions and velocities of every body at `times`, from the angle ODE at rtol 1e-12."""
    angles = np.asarray(angles, dtype=float)
    n = len(angles)
    sol = solve_ivp(angle_rhs, (0.0, float(times[-1])), np.concatenate([angles, np.zeros(n)]),
                    method="DOP853", t_eval=times, rtol=1e-12, atol=1e-12, args=(n, m, L, g))
    th, w = sol.y[:n], sol.y[n:]
    xs, ys = positions(th, L)
    vxs = L * np.cumsum(np.cos(th) * w, axis=0)
    vys = L * np.cumsum(np.sin(th) * w, axis=0)
    out = {}
    for i in range(n):
        out.update({f"x{i + 1}": xs[i], f"y{i + 1}": ys[i], f"vx{i + 1}": vxs[i], f"vy{i + 1}": vys[i]})
    return out
