"""IDAS's linear solver is chosen from the model's size: CasADi's default below the measured
threshold (small models keep their trajectories bit for bit), CSparse's LU from it on
(compiler/runtime/linear_solver.py; compiler/runtime/idas.py applies it, caller's options win)."""
from __future__ import annotations

import numpy as np

from compiler import runtime
from compiler.runtime import linear_solver
from compiler.lower.to_casadi import lower
from tests.runtime import runtime_systems as systems


def test_small_models_keep_the_default_and_large_ones_get_sparse_lu():
    below = linear_solver.SPARSE_LU_FROM - 1
    assert linear_solver.linear_solver_options(below) == {}
    assert linear_solver.linear_solver_options(linear_solver.SPARSE_LU_FROM) == {"linear_solver": "csparse"}


def test_sparse_lu_run_agrees_with_the_default_solver_to_round_off():
    model = lower(systems.mass_chain(20))
    sparse = runtime.simulate(model, 2.0, rtol=1e-8, atol=1e-8, points=21, progress=False,
                              integrator_options=linear_solver.linear_solver_options(60))
    default = runtime.simulate(model, 2.0, rtol=1e-8, atol=1e-8, points=21, progress=False,
                               integrator_options={"linear_solver": "qr"})
    for name in ("s1", "v10", "s20"):
        assert np.max(np.abs(np.asarray(sparse[name]) - np.asarray(default[name]))) < 1e-9
