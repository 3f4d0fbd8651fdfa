"""Consistent initialization: a least-squares solve of the initialization system (Levenberg–
Marquardt with the exact Jacobian), and the restart point of a state-set switch."""
from __future__ import annotations

import math
from typing import Callable

import casadi as ca
import numpy as np

from .errors import InitializationFailed
from .model import CompiledModel
from .pointwise import PointwiseEvaluator


class InitialPoint:
    def __init__(self, x: np.ndarray, z: np.ndarray, iterations: int, residual: float):
        self.x = x
        self.z = z
        self.iterations = iterations
        self.residual = residual


def _row_scales(jac: np.ndarray) -> np.ndarray:
    """|r_i| / scale_i is how far (in the unknowns) residual i is from being satisfied."""
    norms = np.max(np.abs(jac), axis=1) if jac.size else np.zeros(jac.shape[0])
    return np.where(norms > 1e-300, norms, 1.0)


def _finite_jacobian(evaluate: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]):
    """`evaluate` with the Jacobian's infinite or nan entries read as 0: a derivative that does
    not exist at the point (sqrt at 0, an auxiliary `a = x^2 + y^2` guessed 0 under `sqrt(a) = L`)
    gives no direction, and the other rows move the point off the singularity. Unguarded, the
    entry made the row scale infinite and LAPACK's SVD stopped with an internal LinAlgError."""
    def finite(w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        r, jac = evaluate(w)
        return r, np.where(np.isfinite(jac), jac, 0.0)
    return finite


def _levenberg_marquardt(evaluate: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]],
                         w: np.ndarray, tol: float, max_iterations: int):
    """Least-squares solve of r(w) = 0 with the exact Jacobian. Returns (w, r, jac, iterations)."""
    evaluate = _finite_jacobian(evaluate)
    r, jac = evaluate(w)
    lam = 0.0
    iterations = 0
    while r.size and iterations < max_iterations and np.all(np.isfinite(r)):
        if np.max(_scaled_residual(r, jac, w)) <= tol * 1e-3:
            break
        iterations += 1
        # Row-equilibrate so that residuals in Pa and in m weigh alike; More's column scaling.
        rows = _row_scales(jac)
        jr, rr = jac / rows[:, None], r / rows
        cols = np.sqrt(np.sum(jr * jr, axis=0))
        cols = np.where(cols > 1e-300, cols, 1.0)
        cost = 0.5 * float(rr @ rr)
        accepted = False
        for _ in range(30):
            if lam > 0.0:
                a = np.vstack([jr, np.sqrt(lam) * np.diag(cols)])
                b = np.concatenate([-rr, np.zeros(len(w))])
            else:
                a, b = jr, -rr
            step = _linear_least_squares(a, b)
            w_new = w + step
            r_new, jac_new = evaluate(w_new)
            rr_new = r_new / rows
            cost_new = 0.5 * float(rr_new @ rr_new) if np.all(np.isfinite(r_new)) else math.inf
            predicted = cost - 0.5 * float(np.sum((rr + jr @ step) ** 2))
            if cost_new < cost:
                gain = (cost - cost_new) / predicted if predicted > 0 else 1.0
                lam = 0.0 if gain > 0.75 else lam / 3.0 if gain > 0.25 else max(lam, 1e-6)
                accepted = True
                break
            lam = max(1e-6, 10.0 * lam)
        if not accepted:
            break                                  # a (local) least-squares minimum
        tiny_step = np.max(np.abs(step), initial=0.0) <= 1e-15 * (1.0 + np.max(np.abs(w), initial=0.0))
        w, r, jac = w_new, r_new, jac_new
        if tiny_step:
            break
    return w, r, jac, iterations


def _linear_least_squares(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """min |a s - b|: LU for square, QR for tall full-rank systems (both far cheaper than the SVD),
    the minimum-norm SVD solution when `a` is (nearly) rank-deficient or wide."""
    rows, cols = a.shape
    try:
        if rows == cols > 0:
            s = np.linalg.solve(a, b)
            if np.all(np.isfinite(s)) and \
                    np.linalg.norm(a @ s - b) <= 1e-9 * (np.linalg.norm(b) + 1e-300):
                return s
        elif rows > cols > 0:
            q, r = np.linalg.qr(a)
            diagonal = np.abs(np.diag(r))
            if diagonal.min() > 1e-10 * diagonal.max():
                s = np.linalg.solve(r, q.T @ b)
                if np.all(np.isfinite(s)):
                    return s
    except np.linalg.LinAlgError:
        pass
    return np.linalg.lstsq(a, b, rcond=None)[0]


def _polished(evaluate: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]], w: np.ndarray,
              r: np.ndarray, jac: np.ndarray, rounds: int = 3):
    """Full Newton steps from the least-squares solution for as long as they shrink the
    (row-equilibrated) residual: the point then solves the equations to round-off, not only to
    the stopping test, which is relative to the largest unknown. IDAS takes the point as
    consistent to its own tolerance: Andrews' squeezer stopped with a residual of 1.7e-11 whose
    Newton correction of der(epp) was 45 times its IDAS weight at rtol = atol = 1e-12 (the error
    test failed repeatedly at t = 0); after one step it is 0.02 times."""
    evaluate = _finite_jacobian(evaluate)
    for _ in range(rounds):
        if not r.size or not np.all(np.isfinite(r)):
            break
        rows = _row_scales(jac)
        try:
            step = _linear_least_squares(jac / rows[:, None], -r / rows)
        except np.linalg.LinAlgError:
            break
        w_new = w + step
        r_new, jac_new = evaluate(w_new)
        if not np.all(np.isfinite(r_new)) or \
                np.linalg.norm(r_new / rows) >= np.linalg.norm(r / rows):
            break
        w, r, jac = w_new, r_new, jac_new
    return w, r, jac


def conditioning(jac: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """(smallest / largest singular value, left and right singular vectors of the smallest) of
    the initialization Jacobian with its rows and columns equilibrated (units do not count; the
    right vector is given back in the unknowns' own units): near
    0 where the initial conditions determine some direction of the unknowns only to second order
    or not at all (a position fixed by a coordinate at its extremum: Andrews' crank given by a
    dependent angle, issue 25)."""
    if not jac.size:
        return 1.0, np.zeros(jac.shape[0]), np.zeros(jac.shape[1])
    rows = _row_scales(jac)
    scaled = np.where(np.isfinite(jac), jac, 0.0) / rows[:, None]
    cols = np.sqrt(np.sum(scaled * scaled, axis=0))
    cols = np.where(cols > 1e-300, cols, 1.0)
    u, sigma, vt = np.linalg.svd(scaled / cols)
    k = min(scaled.shape) - 1
    ratio = float(sigma[k] / sigma[0]) if sigma[0] > 0 and scaled.shape[0] >= scaled.shape[1] else 0.0
    return ratio, u[:, k], vt[k] / cols


def _scaled_residual(r: np.ndarray, jac: np.ndarray, w: np.ndarray) -> np.ndarray:
    if not np.all(np.isfinite(r)):
        return np.where(np.isfinite(r), np.abs(r), math.inf)
    return np.abs(r) / _row_scales(jac) / (1.0 + np.max(np.abs(w), initial=0.0))


def consistent_initialization(model: CompiledModel, p: np.ndarray, t0: float, *,
                              tol: float = 1e-10, max_iterations: int = 200) -> InitialPoint:
    """Solve init(x, z, p, t0) = 0 in the least-squares sense (Levenberg–Marquardt, exact Jacobian).

    More residuals than unknowns is fine when they are consistent. Success means every residual,
    divided by the largest entry of its Jacobian row, is below `tol * (1 + |w|_inf)`: a
    Newton-step-sized measure that does not depend on the units of the equation.
    """
    nx = len(model.state_names)
    fun = model.init_jacobian()
    # through numpy buffers, not CasADi matrices (excavator: 0.13 -> 0.05 ms an evaluation)
    single = model.derived(("evaluator", "init_jacobian"), lambda: PointwiseEvaluator(fun, block=1))
    n_rows, n_columns = fun.size_out(1)
    times = np.array([float(t0)])

    def evaluate(w_: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        r_, j_ = single.evaluate(w_[:nx, None], w_[nx:, None], p, times)
        return r_[:, 0].copy(), j_[:, 0].reshape(n_columns, n_rows).T.copy()

    w0 = np.concatenate([model.x_guess, model.z_guess]).astype(float)
    from .linear_solver import sparse_initial_point      # large sparse systems: sparse Newton
    sparse = sparse_initial_point(fun, nx, p, t0, w0, tol)
    if sparse is not None:
        return InitialPoint(sparse[0][:nx].copy(), sparse[0][nx:].copy(), sparse[1], sparse[2])
    w, r, jac, iterations = _levenberg_marquardt(evaluate, w0, tol, max_iterations)
    w, r, jac = _polished(evaluate, w, r, jac)
    measure = _scaled_residual(r, jac, w)
    if not np.all(measure <= tol):
        order = np.argsort(-np.nan_to_num(measure, nan=math.inf), kind="stable")
        worst = [(int(i), float(r[i]), _label(model, int(i))) for i in order[:5] if measure[i] > tol]
        lines = "\n".join(f"  residual {i} = {value:.6g}: {label}" for i, value, label in worst)
        raise InitializationFailed(
            f"initialization failed at t = {t0:g}: the initial conditions are inconsistent or "
            f"have no solution near the guesses ({iterations} iterations); largest residuals:\n"
            f"{lines}", t0, worst)
    return InitialPoint(w[:nx].copy(), w[nx:].copy(), iterations, float(np.max(measure, initial=0)))


def _label(model: CompiledModel, index: int) -> str:
    labels = model.init_residual_labels
    return labels[index] if index < len(labels) and labels[index] else f"initial residual #{index}"



def restart_point(model: CompiledModel, p: np.ndarray, t: float, x_target: np.ndarray,
                  z_guess: np.ndarray, tol: float = 1e-10) -> InitialPoint:
    """The point of `model` whose states are `x_target` and whose algebraic unknowns solve
    alg(x, z, p, t) = 0 (from `z_guess`): where a run continues after switching its state set."""
    newton = model.algebraic_newton()
    x = np.asarray(x_target, dtype=float)

    def evaluate(z_: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        r_, j_ = newton(x, z_, p, t)
        return np.asarray(r_, dtype=float).reshape(-1), np.asarray(ca.densify(j_), dtype=float)

    z, r, jac, iterations = _levenberg_marquardt(evaluate, np.asarray(z_guess, dtype=float), tol, 100)
    measure = _scaled_residual(r, jac, z)
    if not np.all(measure <= tol * 1e3):
        worst = int(np.argmax(np.nan_to_num(measure, nan=math.inf)))
        raise InitializationFailed(f"no consistent point after switching the state set of "
                                   f"{model.name} at t = {t:.10g} (algebraic residual {worst} = "
                                   f"{r[worst]:.3g})", t, [(worst, float(r[worst]), "")])
    return InitialPoint(x.copy(), z, iterations, float(np.max(measure, initial=0)))
