"""Polishing: the algebraic unknowns z at the output times moved onto their equations.

IDAS interpolates z between its steps, so at output times the algebraic equations hold only to
the interpolation error (excavator, rtol 1e-6: z off by up to 12 %). With the states fixed, a
Newton step on 0 = alg(x, z) makes them hold to round-off (the constraint of a mechanism to
~1e-15). A step is kept only where it does not increase the largest residual; a further step is
taken only at the points where it would still move z (SETTLED).

Where the algebraic system is small (FUSED_UP_TO unknowns), one step is one function of
(x, z, p, t) (`newton_step_function`): the residual and its Jacobian, the step solved in closed
form, whether it is kept and the next step's estimate, the subexpressions of x alone computed
once for both residuals (excavator: 902 SX instructions against 751 + 599 for the Newton function
and the residual apart); the run's outputs are evaluated in the same function, at the z of that
step (`polished_outputs_function`, outputs.signals_at; with `--codegen c` it is in the model's
library, compiler/lower/ccodegen.py). Larger systems: the Newton function and the residual, the
steps solved by numpy's batched LU; large sparse ones point by point (linear_solver.sparse_polish).
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from .model import CompiledModel
from .pointwise import evaluator, parameter_runs

# A further Newton step is taken only at points where it would move some z_i by more than this,
# relative to |z_i| + the largest |z_i| of the points polished together. It is estimated with the
# Jacobian of the step before (a chord step: at the residual's round-off level it is the Newton
# step to a few digits). Excavator, rtol 1e-6, 1201 points: one step leaves z within 3e-12 of
# what two give (the residual's round-off: a second step moves z by as much again), so the
# second step, 40 % of the polishing, is never taken there.
SETTLED = 1e-10
# The largest algebraic system whose Newton step is solved in closed form inside one function:
# the two solves of a dense n x n system cost 151 SX instructions at n = 3, 396 at 4, 1170 at 6
# (numpy's batched solve: about 0.15 us a point either way).
FUSED_UP_TO = 4


def polish_algebraics(model: CompiledModel, xs: np.ndarray, zs: np.ndarray, p: np.ndarray,
                      grid: np.ndarray, iterations: int = 2, settled: float = SETTLED) -> np.ndarray:
    """z at the points (xs, zs) of `grid` after at most `iterations` Newton steps (see the
    module's docstring); `p` is one parameter vector or one column per point. `settled` 0 takes
    every step (a point a run restarts from: a state-set switch)."""
    nz, n = zs.shape
    if nz == 0 or n == 0:
        return zs
    from .linear_solver import sparse_polish      # large sparse systems: sparse, point by point
    polished = sparse_polish(model, xs, zs, p, grid, iterations)
    if polished is not None:
        return polished
    step = newton_step(model)
    z = np.array(zs, dtype=float)
    times = np.asarray(grid, dtype=float)
    for first, last, p_run in parameter_runs(p, n):
        z[:, first:last] = polish_run(step, xs[:, first:last], z[:, first:last], p_run,
                                      times[first:last], iterations, settled)
    return z


def polish_run(step, xs, z, p, times, iterations: int = 2, settled: float = SETTLED,
               first=None) -> np.ndarray:
    """The Newton steps on points that share p (z is overwritten), each from the points the one
    before left unsettled. `first`: the first step's (z, kept, moves) where it is evaluated
    already (outputs.signals_at evaluates it with the outputs)."""
    scale = np.abs(z).max(axis=1, keepdims=True)
    active = np.arange(z.shape[1])
    for iteration in range(iterations):
        sub = slice(None) if iteration == 0 else active
        z_next, kept, moves = first if iteration == 0 and first is not None else \
            step(xs[:, sub], z[:, sub], p, times[sub])
        z[:, active] = z_next
        active = active[kept & np.any(np.abs(moves) > settled * (np.abs(z_next) + scale), axis=0)]
        if active.size == 0:
            break
    return z


def newton_step(model: CompiledModel):
    """step(xs, zs, p, times) -> (z after one Newton step where it is kept, else as given; kept;
    the estimate of the next step), evaluated over the points at once."""
    nz = len(model.algebraic_names)
    if nz <= FUSED_UP_TO:
        fused = evaluator(model, ("newton_step",), lambda: newton_step_function(model))

        def step(xs, zs, p, times):
            z_next, kept, moves = fused.evaluate(xs, zs, p, times)
            return z_next, kept[0] > 0, moves
        return step
    newton = evaluator(model, ("algebraic_newton",),
                       lambda: model.native_function("algebraic_newton") or model.algebraic_newton())
    residual = evaluator(model, ("algebraic_residual",),
                         lambda: model.native_function("algebraic_residual") or residual_function(model))

    def solved(xs, zs, p, times):
        r, jac = newton.evaluate(xs, zs, p, times)
        matrices = jac.T.reshape(zs.shape[1], nz, nz).transpose(0, 2, 1)      # column-major per point
        try:
            candidate = zs - _solve(matrices, r)
            (r_new,) = residual.evaluate(xs, candidate, p, times)
            kept = np.all(np.isfinite(r_new), axis=0) & (np.abs(r_new).max(axis=0) <= np.abs(r).max(axis=0))
            return np.where(kept, candidate, zs), kept, _solve(matrices, np.nan_to_num(r_new))
        except np.linalg.LinAlgError:             # a singular Jacobian: no step anywhere
            return zs, np.zeros(zs.shape[1], dtype=bool), np.zeros_like(zs)
    return solved


def _solve(matrices: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """matrices[k] @ step[:, k] = rhs[:, k] for every point k."""
    return np.linalg.solve(matrices, rhs.T[:, :, None])[:, :, 0].T


def _step_expressions(model: CompiledModel):
    """(symbols x, z, p, t; z after one Newton step on r = alg(x, z, p, t) = 0 where it is kept,
    else z; whether it is kept: r at the candidate finite and its largest |entry| no larger; the
    chord estimate of the next step, J \\ r(candidate) with J = dr/dz at z)."""
    x, z, p, t = model.symbols()
    alg = model.dae(x, z, p, t)[1]
    jac = ca.jacobian(alg, z)
    candidate = z - ca.solve(jac, alg)
    alg_there = ca.substitute(alg, z, candidate)        # the terms in x alone stay shared
    finite = ca.logic_and(ca.mmin(ca.lt(ca.fabs(alg_there), ca.inf)), ca.mmin(ca.eq(alg, alg)))
    kept = ca.logic_and(finite, ca.le(ca.mmax(ca.fabs(alg_there)), ca.mmax(ca.fabs(alg))))
    return (x, z, p, t), ca.if_else(kept, candidate, z), kept, ca.solve(jac, alg_there)


def newton_step_function(model: CompiledModel, name: str = "alg_newton_step") -> ca.Function:
    """(x, z, p, t) -> (z after one kept Newton step, kept, next step's estimate): the step of a
    small algebraic system (FUSED_UP_TO) in one function."""
    symbols, z_next, kept, moves = _step_expressions(model)
    return ca.Function(name, list(symbols), ca.cse([z_next, kept, moves]))


def polished_outputs_function(model: CompiledModel, rows, name: str = "outputs_polished") -> ca.Function:
    """(x, z, p, t) -> (the outputs `rows` (None: all) at z after one kept Newton step, that z,
    kept, next step's estimate): polishing and outputs in one pass (outputs.signals_at)."""
    symbols, z_next, kept, moves = _step_expressions(model)
    x, z, p, t = symbols
    values = model.outputs(x, z, p, t)
    if rows is not None:
        values = values[list(rows)] if len(rows) else ca.SX(0, 1)
    # common subexpressions of the outputs and the algebraic equations computed once (excavator:
    # 2855 -> 2282 SX instructions, the same numbers)
    return ca.Function(name, list(symbols), ca.cse([ca.substitute(values, z, z_next), z_next, kept, moves]))


def residual_function(model: CompiledModel) -> ca.Function:
    """(x, z, p, t) -> alg, the same expressions as the first output of algebraic_newton."""
    x, z, p, t = model.symbols()
    return ca.Function("alg_residual", [x, z, p, t], [model.dae(x, z, p, t)[1]])
