"""Models without states: nothing to integrate, so the algebraic equations are solved at every
output time, each solve starting from the previous solution."""
from __future__ import annotations

import casadi as ca
import numpy as np

from .errors import SimulationFailed
from .initialization import _levenberg_marquardt, _scaled_residual
from .model import CompiledModel
from .outputs import evaluate_outputs
from .progress import Progress

_TOLERANCE = 1e-12


def solve_static(model: CompiledModel, grid: np.ndarray, p: np.ndarray, z0: np.ndarray,
                 counters: dict, progress: Progress) -> np.ndarray:
    """Every output of the model at every grid time (z0 solves the equations at grid[0])."""
    def build():
        x, z, p_, t = model.symbols()
        alg = model.dae(x, z, p_, t)[1]
        return ca.Function("alg_jac", [z, p_, t], [alg, ca.jacobian(alg, z)])
    fun = model.derived("static_newton", build)
    zs = np.empty((len(model.algebraic_names), len(grid)))
    zs[:, 0] = z0
    for k in range(1, len(grid)):
        def evaluate(z_: np.ndarray, t_=grid[k]) -> tuple[np.ndarray, np.ndarray]:
            r_, j_ = fun(z_, p, t_)
            return np.asarray(r_, dtype=float).reshape(-1), np.asarray(ca.densify(j_), dtype=float)
        z, r, jac, iterations = _levenberg_marquardt(evaluate, zs[:, k - 1].copy(), _TOLERANCE, 100)
        counters["newton_iterations"] = counters.get("newton_iterations", 0) + iterations
        if not np.all(_scaled_residual(r, jac, z) <= _TOLERANCE * 1e3):
            reason = "the algebraic equations have no solution near the previous one"
            raise SimulationFailed(f"simulation of {model.name} failed at t = {grid[k]:.10g}: "
                                   f"{reason}", float(grid[k - 1]), reason)
        zs[:, k] = z
        counters["steps"] = counters.get("steps", 0) + 1
        progress.update(grid[k])
    return evaluate_outputs(model, np.zeros((0, len(grid))), zs, p, grid)
