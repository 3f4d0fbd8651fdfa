"""Where the equations IDAS solves together stop determining their unknowns (run_failures.py): the
smallest singular value of the Jacobian of the algebraic equations with respect to the algebraic
unknowns, along a run towards a failure. This is what the solve divides by: a mass matrix or a
constraint Jacobian losing rank makes the pivots of its factorization vanish, whichever of its
entries pass through 0 on the way (Andrews' squeezer's off-diagonal entries do, harmlessly).

The run towards the failure records the states and the named signals; derivative unknowns (der(u)
solved in a block) are not among them, so the algebraic unknowns are solved again at each point,
by Newton's method from the recorded values (0 where none is recorded).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import casadi as ca
import numpy as np

NEWTON_STEPS = 8


@dataclass(frozen=True)
class BlockTrend:
    smallest: np.ndarray        # the smallest singular value at each time (nan where unsolved)
    rows: list[int]             # algebraic equations, most involved in the vanishing pivot first
    unknowns: list[str]         # algebraic unknowns, likewise


def smallest_pivots(model, parameter_values: Mapping[str, float], env: Mapping[str, np.ndarray],
                    times: np.ndarray) -> BlockTrend | None:
    """The trend of the algebraic Jacobian's smallest singular value over `times`, for a model
    with states and algebraic unknowns; None where the points cannot be rebuilt. (With one
    unknown it is that equation's derivative with respect to it, the assignments it reads
    included: the Schur complement of a mass matrix torn down to one unknown.)"""
    nz = len(model.algebraic_names)
    if nz < 1 or not model.state_names or any(n not in env for n in model.state_names):
        return None
    tunable = {n for n, free in zip(model.parameter_names, model.parameter_tunable) if free}
    try:
        p = model.parameter_vector({n: v for n, v in parameter_values.items() if n in tunable})
    except Exception:           # noqa: BLE001 - no parameter vector: nothing to evaluate
        return None
    newton = model.algebraic_newton()
    smallest = np.full(len(times), np.nan)
    vectors = None
    z = np.array([float(env[n][0]) if n in env else 0.0 for n in model.algebraic_names])
    for k, t in enumerate(times):
        x = np.array([float(env[n][k]) for n in model.state_names])
        recorded = np.array([float(env[n][k]) if n in env else z[i]
                             for i, n in enumerate(model.algebraic_names)])
        solved = _solve(newton, x, recorded, p, float(t))
        if solved is None:
            continue
        z, jacobian = solved
        u, sigma, vt = np.linalg.svd(jacobian)
        smallest[k] = sigma[-1]
        vectors = (u[:, -1], vt[-1])
    if vectors is None:
        return None
    rows = [int(i) for i in np.argsort(-np.abs(vectors[0]), kind="stable")]
    unknowns = [model.algebraic_names[int(i)] for i in np.argsort(-np.abs(vectors[1]), kind="stable")]
    return BlockTrend(smallest, rows, unknowns)


def _solve(newton, x, z, p, t):
    """(z, d alg / d z) with alg(x, z) = 0 from z, or None when Newton does not get there."""
    for _ in range(NEWTON_STEPS):
        residual, jacobian = newton(x, z, p, t)
        residual = np.asarray(residual, dtype=float).ravel()
        jacobian = np.asarray(ca.densify(jacobian), dtype=float)
        if not (np.all(np.isfinite(residual)) and np.all(np.isfinite(jacobian))):
            return None
        scale = 1.0 + np.max(np.abs(z), initial=0.0)
        step = np.linalg.lstsq(jacobian, -residual, rcond=None)[0]
        z = z + step
        if np.max(np.abs(step), initial=0.0) <= 1e-12 * scale:
            return z, jacobian
    residual = np.asarray(newton(x, z, p, t)[0], dtype=float).ravel()
    return None if np.max(np.abs(residual), initial=0.0) > 1e-8 * (1.0 + np.max(np.abs(z))) else (z, jacobian)
