"""Which linear solver IDAS's Newton iteration uses, chosen from the size and the sparsity of the
model's Jacobian; and Newton solves on large sparse systems outside IDAS.

CasADi's IDAS factorizes the iteration matrix dF/dy' * c + dF/dy with one of CasADi's linear
solver plugins (option `linear_solver`; its default is CasADi's own sparse QR, "qr", which orders
the columns to reduce fill). Small models (below SPARSE_LU_FROM unknowns: the excavator, every
golden trajectory) and sparse Jacobians keep that default, so their trajectories stay bit for
bit; large dense Jacobians (the torn form of a long chain) get CSparse's LU, the fastest there.
Options the caller passes (integrator_options) win. The measurements behind the thresholds:
docs/scaling.md, "Which linear solver".
"""
from __future__ import annotations

import casadi as ca
import numpy as np

# Unknowns (states + IDAS algebraics) from which the Jacobian's sparsity decides.
SPARSE_LU_FROM = 40
SPARSE_LU = "csparse"
# Structural density of d[ode; alg]/d[x; z] below which the Jacobian counts as sparse: CasADi's
# QR (fill-reducing order) stays; at or above, CSparse's LU. The torn chain has 0.33-0.37, the
# sparse form 0.004-0.065 (N = 16 ... 256).
SPARSE_BELOW = 0.1
# Newton solves outside IDAS (initialization, polishing) go sparse from this many unknowns.
SPARSE_NEWTON_FROM = 100


def linear_solver_options(n_unknowns: int, model=None) -> dict:
    """IDAS options for a DAE with `n_unknowns` unknowns: {} keeps CasADi's default."""
    if n_unknowns < SPARSE_LU_FROM or not ca.has_linsol(SPARSE_LU):
        return {}
    if model is not None and jacobian_density(model) < SPARSE_BELOW:
        return {}
    return {"linear_solver": SPARSE_LU}


def jacobian_density(model) -> float:
    """Structural density of the DAE's Jacobian d[ode; alg]/d[x; z] (kept per model)."""
    def build() -> float:
        nx, nz, _ = model.sizes
        if nx + nz == 0:
            return 0.0
        x, z, p, t = model.symbols()
        ode, alg = model.dae(x, z, p, t)
        pattern = ca.jacobian_sparsity(ca.vertcat(ode, alg), ca.vertcat(x, z))
        return pattern.nnz() / float((nx + nz) ** 2)
    return model.derived("jacobian_density", build)


def is_large_sparse(n_unknowns: int, jacobian: ca.DM) -> bool:
    """Whether a Newton system outside IDAS should be solved sparse (never for small models)."""
    rows, cols = jacobian.shape
    return n_unknowns >= SPARSE_NEWTON_FROM and rows == cols and \
        jacobian.nnz() < SPARSE_BELOW * rows * cols


def sparse_newton(evaluate, w: np.ndarray, tol: float, max_iterations: int = 30):
    """Plain Newton steps on a square sparse system, solved by CasADi's sparse QR; `evaluate(w)`
    gives (r as numpy, J as a sparse DM). Returns (w, r, J, iterations, converged), converged
    when every |r_i| / max|J_i.| <= tol * (1 + |w|_inf) (initialization's own test)."""
    r, jac = evaluate(w)
    solver = _SparseSolver(jac)
    for iteration in range(max_iterations + 1):
        if not np.all(np.isfinite(r)):
            return w, r, jac, iteration, False
        if np.all(np.abs(r) / _row_maxima(jac) <= tol * (1.0 + np.max(np.abs(w), initial=0.0))):
            return w, r, jac, iteration, True
        if iteration == max_iterations:
            break
        w = w - solver.solve(jac, r)
        r, jac = evaluate(w)
    return w, r, jac, max_iterations, False


class _SparseSolver:
    """CasADi's sparse QR for one sparsity pattern: the symbolic factorization (column order)
    once, a numeric one per matrix (ca.solve would redo both: 12x slower at 2000 unknowns)."""

    def __init__(self, jac: ca.DM):
        self._linsol = ca.Linsol("sparse_newton", "qr", jac.sparsity())

    def solve(self, jac: ca.DM, r: np.ndarray) -> np.ndarray:
        return np.asarray(self._linsol.solve(jac, ca.DM(r)), dtype=float).reshape(-1)


def _row_maxima(jac: ca.DM) -> np.ndarray:
    values = np.abs(np.asarray(jac.nonzeros(), dtype=float))
    rows = np.asarray(jac.sparsity().get_triplet()[0], dtype=int)
    maxima = np.zeros(jac.shape[0])
    np.maximum.at(maxima, rows, values)
    return np.where(maxima > 1e-300, maxima, 1.0)


def sparse_initial_point(init_jacobian: ca.Function, nx: int, p: np.ndarray, t0: float,
                         w0: np.ndarray, tol: float):
    """Consistent initialization of a large sparse square system by sparse Newton steps (the
    dense Levenberg-Marquardt path costs O(n^3) per step and, from zero guesses, took 24 damped
    steps on the 16-link chain's sparse form; Newton takes 3-4 at every N measured). Returns
    (w, iterations, scaled residual) or None: small or dense systems, or no convergence (the
    caller's Levenberg-Marquardt then starts from w0 as before)."""
    def evaluate(w):
        r, jac = init_jacobian(w[:nx], w[nx:], p, t0)
        return np.asarray(r, dtype=float).reshape(-1), jac

    if len(w0) < SPARSE_NEWTON_FROM:               # small: dense, and no evaluation to decide it
        return None
    r, jac = evaluate(np.asarray(w0, dtype=float))
    if not is_large_sparse(len(w0), jac):
        return None
    w, r, jac, iterations, converged = sparse_newton(evaluate, np.asarray(w0, dtype=float), tol * 1e-3)
    if not converged:
        return None
    measure = np.abs(r) / _row_maxima(jac) / (1.0 + np.max(np.abs(w), initial=0.0))
    return w, iterations, float(np.max(measure, initial=0.0))


def sparse_polish(model, xs: np.ndarray, zs: np.ndarray, p: np.ndarray, grid: np.ndarray,
                  iterations: int):
    """outputs.polish_algebraics for large sparse algebraic systems: the same Newton steps on
    0 = alg(x, z) with the states fixed, each kept only where it does not increase the largest
    residual, solved sparse point by point (the dense batch would hold nz^2 numbers per point).
    None for small or dense systems (the caller's dense path)."""
    nz, n = zs.shape
    newton = model.algebraic_newton()
    p = np.asarray(p, dtype=float)
    columns = p.ndim == 2 and p.shape[1] == n and p.shape[1] > 1

    def evaluate(j, z):
        r, jac = newton(xs[:, j], z, p[:, j] if columns else p.reshape(-1), float(grid[j]))
        return np.asarray(r, dtype=float).reshape(-1), jac

    if nz < SPARSE_NEWTON_FROM or n == 0:
        return None
    r, jac = evaluate(0, zs[:, 0])
    if not is_large_sparse(nz, jac):
        return None
    z = np.array(zs, dtype=float)
    solver = _SparseSolver(jac)
    for j in range(n):
        r, jac = evaluate(j, z[:, j]) if j else (r, jac)
        for _ in range(iterations):
            candidate = z[:, j] - solver.solve(jac, r)
            r_new, jac_new = evaluate(j, candidate)
            if not np.all(np.isfinite(r_new)) or np.max(np.abs(r_new)) > np.max(np.abs(r)):
                break
            z[:, j], r, jac = candidate, r_new, jac_new
    return z
