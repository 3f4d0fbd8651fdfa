"""Large systems whose torn form would be dense get the sparse form (compiler/structure/
causalize.py: chains of assignments cut where their fan-in exceeds a bound, the cut values become
IDAS unknowns), IDAS keeps CasADi's sparse QR on them, initialization and polishing solve sparse
(compiler/runtime/linear_solver.py). Small systems keep today's torn form."""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from compiler import runtime
from compiler.pipeline import compile_spec
from compiler.runtime import linear_solver
from compiler.structure import causalize

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
from suite.chain_model import write_chain  # noqa: E402


def _compile(tmp_path, n: int, monkeypatch=None, form: str = "chosen"):
    """The chain compiled in the form chosen automatically, or forced "torn" or "sparse" (the
    automatic choice takes the sparse form from 150 torn unknowns: N = 50; N = 16 keeps the
    tests fast)."""
    if form == "torn":
        monkeypatch.setattr(causalize, "DENSE_FROM", 2.0)      # never dense enough: torn form
    elif form == "sparse":
        monkeypatch.setattr(causalize, "SPARSE_FORM_FROM", 40)
    model = compile_spec(write_chain(n, tmp_path)).model
    if monkeypatch is not None:
        monkeypatch.undo()
    return model


def test_small_chain_keeps_the_torn_form(tmp_path):
    model = _compile(tmp_path, 4)
    nx, nz, _ = model.sizes
    assert (nx, nz) == (8, 4)                        # states and the N torn accelerations


def test_large_chain_gets_the_sparse_form_and_the_same_trajectory(tmp_path, monkeypatch):
    assert _compile(tmp_path, 16).sizes[1] == 16      # chosen: torn below the threshold
    sparse = _compile(tmp_path, 16, monkeypatch, form="sparse")
    torn = _compile(tmp_path, 16, monkeypatch, form="torn")
    assert torn.sizes[1] == 16 and sparse.sizes[1] > 100
    assert linear_solver.jacobian_density(torn) > 0.3
    assert linear_solver.jacobian_density(sparse) < linear_solver.SPARSE_BELOW
    # IDAS keeps its sparse QR on the sparse form, CSparse's LU on the dense torn form
    assert linear_solver.linear_solver_options(sum(sparse.sizes[:2]), sparse) == {}
    assert linear_solver.linear_solver_options(sum(torn.sizes[:2]), torn) == {"linear_solver": "csparse"}
    runs = [runtime.simulate(m, 0.5, rtol=1e-6, atol=1e-6, points=51, progress=False)
            for m in (sparse, torn)]
    for name in ("joints[1].phi", "joints[16].phi", "joints[16].w"):
        a, b = (np.asarray(run[name]) for run in runs)
        # two discretizations at rtol 1e-6 (IDAS takes different steps): rtol-level agreement
        assert np.max(np.abs(a - b)) < 5e-6 * (1.0 + np.max(np.abs(b)))
    # an algebraic signal (polished sparse in one form, dense in the other) agrees as well
    name = "links[16].frame_b.fx"
    a, b = (np.asarray(run[name]) for run in runs)
    assert np.max(np.abs(a - b)) < 1e-5 * (1.0 + np.max(np.abs(b)))


def test_the_automatic_choice_takes_the_sparse_form_above_the_threshold(tmp_path):
    n = causalize.SPARSE_FORM_FROM // 3 + 1               # torn: 3n unknowns, just above
    model = _compile(tmp_path, n)
    assert model.sizes[1] > 3 * n
    assert linear_solver.jacobian_density(model) < linear_solver.SPARSE_BELOW


def test_sparse_initialization_solves_to_the_initialization_tolerance(tmp_path, monkeypatch):
    model = _compile(tmp_path, 16, monkeypatch, form="sparse")
    nx = model.sizes[0]
    p = np.asarray(model.parameter_defaults, dtype=float)
    w0 = np.concatenate([model.x_guess, model.z_guess]).astype(float)
    point = linear_solver.sparse_initial_point(model.init_jacobian(), nx, p, 0.0, w0, 1e-10)
    assert point is not None
    w, iterations, residual = point
    assert iterations <= 10 and residual <= 1e-13
    r, _ = model.init_jacobian()(w[:nx], w[nx:], p, 0.0)
    assert np.max(np.abs(np.asarray(r))) < 1e-9


@pytest.mark.parametrize("n_unknowns", [linear_solver.SPARSE_LU_FROM - 1])
def test_small_systems_never_take_the_sparse_paths(n_unknowns):
    import casadi as ca
    identity = ca.DM.eye(n_unknowns)
    assert not linear_solver.is_large_sparse(n_unknowns, identity)
    assert linear_solver.linear_solver_options(n_unknowns) == {}
