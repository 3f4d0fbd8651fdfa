"""Which states and inputs each derivative depends on, for the ModelStructure of an FMU.

With the algebraic unknowns eliminated, d der(x) / d(x, u) = f_k - f_z g_z^-1 g_k (k: the states
and inputs; compiler/linear/elimination.py). Its structural pattern is that of the same product
over matrices holding independent random values in the structural nonzeros of f_k, f_z, g_z and
g_k (the sparsity CasADi knows): an entry that is structurally nonzero is nonzero for almost every
choice of values, so one fixed-seed sample gives the pattern, with no symbolic inversion of g_z.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from compiler.fmu.layout import FmuLayout
from compiler.runtime import CompiledModel

_SEED = 20261128


def _sample(sparsity: ca.Sparsity, rng: np.random.Generator) -> np.ndarray:
    matrix = np.zeros(sparsity.shape)
    rows, columns = sparsity.get_triplet()
    matrix[rows, columns] = rng.uniform(1.0, 2.0, len(rows)) * rng.choice([-1.0, 1.0], len(rows))
    return matrix


def derivative_dependencies(model: CompiledModel, layout: FmuLayout) -> list[list[int]]:
    """For each state's derivative, the positions among (states, then inputs) it depends on."""
    x, z, p, t = model.symbols()
    ode, alg = model.dae(x, z, p, t)
    inputs = [p[i] for i in layout.input_parameters]
    known = ca.vertcat(x, *inputs)
    rng = np.random.default_rng(_SEED)
    f_known = _sample(ca.jacobian(ode, known).sparsity(), rng)
    structural = f_known != 0
    if z.numel():
        f_z, g_z, g_known = (_sample(ca.jacobian(a, b).sparsity(), rng)
                             for a, b in ((ode, z), (alg, z), (alg, known)))
        try:
            eliminated = f_known - f_z @ np.linalg.solve(g_z, g_known)
        except np.linalg.LinAlgError:          # singular pattern: claim every dependency
            eliminated = np.ones_like(f_known)
        scale = max(np.abs(eliminated).max(initial=0.0), 1.0)
        structural = structural | (np.abs(eliminated) > 1e-9 * scale)
    return [[int(j) for j in np.nonzero(row)[0]] for row in structural]
