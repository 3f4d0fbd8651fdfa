"""From the integrator's (x, z) at the output times to the user's signals: algebraic unknowns
polished onto their equations, then every output in one vectorized call."""
from __future__ import annotations

import casadi as ca
import numpy as np

from .model import CompiledModel


def polish_algebraics(model: CompiledModel, xs: np.ndarray, zs: np.ndarray, p: np.ndarray,
                      grid: np.ndarray, iterations: int = 2) -> np.ndarray:
    """IDAS interpolates z between its steps, so at output times the algebraic equations hold only
    to the interpolation error. With the states fixed, a couple of Newton steps on 0 = alg(x, z)
    make the outputs satisfy them to round-off (the constraint of a mechanism to ~1e-15)."""
    nz, n = zs.shape
    if nz == 0 or n == 0:
        return zs
    newton = model.derived(("algebraic_newton_map", n), lambda: model.algebraic_newton().map(n))
    pp = _per_point(p, n)
    times = np.asarray(grid, dtype=float).reshape(1, -1)
    z = zs.copy()
    for _ in range(iterations):
        r, jac = newton(xs, z, pp, times)
        r = np.asarray(r, dtype=float).reshape(nz, n)
        jac = np.asarray(ca.densify(jac), dtype=float).reshape(nz, n, nz).transpose(1, 0, 2)
        try:
            step = np.linalg.solve(jac, r.T[:, :, None])[:, :, 0].T
        except np.linalg.LinAlgError:
            return z
        candidate = z - step
        r_new = np.asarray(newton(xs, candidate, pp, times)[0], dtype=float).reshape(nz, n)
        better = np.all(np.isfinite(r_new), axis=0) & (np.abs(r_new).max(axis=0) <= np.abs(r).max(axis=0))
        z[:, better] = candidate[:, better]
    return z


def evaluate_outputs(model: CompiledModel, xs: np.ndarray, zs: np.ndarray, p: np.ndarray,
                     grid: np.ndarray) -> np.ndarray:
    """Every output at every time of `grid`: an (outputs x times) array; `p` is one parameter
    vector or one column per time."""
    n = len(grid)
    if not model.output_names:
        return np.zeros((0, n))
    mapped = model.derived(("outputs_map", n), lambda: model.outputs.map(n))
    out = mapped(xs, zs, _per_point(p, n), np.asarray(grid).reshape(1, -1))
    return np.asarray(out, dtype=float).reshape(len(model.output_names), n)


def _per_point(p: np.ndarray, n: int) -> np.ndarray:
    """The parameters as one column per point: one vector for all, or already a column each."""
    p = np.asarray(p, dtype=float)
    return p if p.ndim == 2 else np.repeat(p.reshape(-1, 1), n, axis=1)
