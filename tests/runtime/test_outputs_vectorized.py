"""The vectorized output path (compiler/runtime/outputs.py) gives what evaluating the model's
functions point by point gives: outputs, a subset of them, per-segment parameters, polishing."""
from __future__ import annotations

import copy
import pickle

import casadi as ca
import numpy as np
import pytest

from compiler.runtime import CompiledModel, ModelInputError, polishing, simulate
from compiler.runtime.outputs import (BLOCK, PointwiseEvaluator, evaluate_outputs, output_rows_function,
                                      polish_algebraics, signals_at)

POINTS = 3 * BLOCK + 5               # whole blocks and a remainder


def small_model(nz: int = 2) -> CompiledModel:
    """x' = -a x + z0, 0 = z0^3 + z0 - x0 * b (and 0 = z1 - sin(z0) - c t); outputs on x only, on
    z, and a constant."""
    x, p, t = ca.SX.sym("x", 2), ca.SX.sym("p", 3), ca.SX.sym("t")
    z = ca.SX.sym("z", nz)
    a, b, c = p[0], p[1], p[2]
    if nz:
        ode = ca.vertcat(-a * x[0] + z[0], x[0] - x[1])
        alg = ca.vertcat(z[0] ** 3 + z[0] - x[0] * b, z[1] - ca.sin(z[0]) - c * t)
        outputs = ca.vertcat(x[0], x[1] * x[0], z[0], z[1] * x[1] + t, ca.exp(-a * t), 2.5)
        names = ["x0", "x0x1", "z0", "z1x1", "decay", "constant"]
    else:
        ode, alg = ca.vertcat(-a * x[0], x[0] - x[1]), ca.SX(0, 1)
        outputs, names = ca.vertcat(x[0], x[1] * b + t), ["x0", "x1b"]
    pu, mask = ca.SX.sym("pu", 3), ca.SX.sym("m", 3)
    return CompiledModel(
        name="Small", state_names=["x0", "x1"], algebraic_names=[f"z{i}" for i in range(nz)],
        parameter_names=["a", "b", "c"], parameter_defaults=[0.7, 1.3, 0.2], output_names=names,
        x_guess=[1.0, 0.0], z_guess=[0.0] * nz,
        dae=ca.Function("dae", [x, z, p, t], [ode, alg]),
        init=ca.Function("init", [x, z, p, t], [ca.vertcat(x[0] - 1, x[1], alg)]),
        outputs=ca.Function("outputs", [x, z, p, t], [outputs]),
        params=ca.Function("params", [pu, mask], [pu]))


def points(model: CompiledModel, seed: int = 0):
    rng = np.random.default_rng(seed)
    nx, nz, _ = model.sizes
    return (rng.normal(size=(nx, POINTS)), rng.normal(size=(nz, POINTS)),
            np.sort(rng.uniform(0.0, 5.0, POINTS)))


def one_by_one(function: ca.Function, xs, zs, p, times) -> np.ndarray:
    """The plain CasADi call at every point (p: one vector, or one column per point)."""
    p = np.asarray(p, dtype=float)
    columns = [np.asarray(ca.densify(function(xs[:, k], zs[:, k], p if p.ndim == 1 else p[:, k], times[k])),
                          dtype=float).reshape(-1) for k in range(len(times))]
    return np.column_stack(columns)


def test_every_output_equals_the_point_by_point_evaluation():
    model = small_model()
    xs, zs, times = points(model)
    p = model.parameter_vector()
    got = evaluate_outputs(model, xs, zs, p, times)
    np.testing.assert_allclose(got, one_by_one(model.outputs, xs, zs, p, times), rtol=1e-15, atol=1e-300)


def test_asked_rows_equal_those_rows_of_every_output():
    model = small_model()
    xs, zs, times = points(model, 1)
    p = model.parameter_vector()
    rows = [3, 0, 4]
    got = evaluate_outputs(model, xs, zs, p, times, rows)
    np.testing.assert_allclose(got, one_by_one(model.outputs, xs, zs, p, times)[rows], rtol=1e-15, atol=1e-300)
    assert evaluate_outputs(model, xs, zs, p, times, []).shape == (0, POINTS)


def test_a_parameter_column_per_point_is_honoured_run_by_run():
    model = small_model()
    xs, zs, times = points(model, 2)
    p = np.repeat(model.parameter_vector().reshape(-1, 1), POINTS, axis=1)
    p[0, 70:] = 0.1                       # a second segment with another parameter value
    p[2, 150:] = -3.0                     # and a third
    got = evaluate_outputs(model, xs, zs, p, times)
    np.testing.assert_allclose(got, one_by_one(model.outputs, xs, zs, p, times), rtol=1e-15, atol=1e-300)


def newton_reference(model: CompiledModel, x, z, p, t, iterations: int = 2) -> np.ndarray:
    """The polishing rule at one point: a Newton step on alg, kept where the residual does not grow."""
    newton = model.algebraic_newton()
    z = np.array(z, dtype=float)
    for _ in range(iterations):
        r, jac = (np.asarray(ca.densify(v), dtype=float) for v in newton(x, z, p, t))
        candidate = z - np.linalg.solve(jac, r.reshape(-1))
        r_new = np.asarray(newton(x, candidate, p, t)[0], dtype=float).reshape(-1)
        if np.all(np.isfinite(r_new)) and np.abs(r_new).max() <= np.abs(r).max():
            z = candidate
    return z


def test_polishing_equals_the_point_by_point_newton_steps_and_solves_the_equations():
    model = small_model()
    xs, _, times = points(model, 3)
    p = model.parameter_vector()
    b, c = p[1], p[2]
    # near the solution, as IDAS's interpolation leaves them
    z0 = np.array([min(np.roots([1, 0, 1, -x * b]), key=lambda root: abs(root.imag)).real for x in xs[0]])
    zs = np.vstack([z0, np.sin(z0) + c * times]) + 1e-4
    got = polish_algebraics(model, xs, zs, p, times)
    expected = np.column_stack([newton_reference(model, xs[:, k], zs[:, k], p, times[k])
                                for k in range(POINTS)])
    np.testing.assert_allclose(got, expected, rtol=1e-15, atol=1e-300)
    inputs = model.dae.sx_in()
    residual = one_by_one(ca.Function("alg", inputs, [model.dae(*inputs)[1]]), xs, got, p, times)
    assert np.abs(residual).max() < 1e-12
    assert np.array_equal(zs, np.vstack([z0, np.sin(z0) + c * times]) + 1e-4)      # input unchanged


@pytest.mark.parametrize("fused_up_to", [4, 0])        # the one-function step, and numpy's solves
def test_a_second_newton_step_is_taken_only_where_the_first_leaves_z_unsettled(monkeypatch, fused_up_to):
    monkeypatch.setattr(polishing, "FUSED_UP_TO", fused_up_to)
    model = small_model()
    xs, _, times = points(model, 3)
    p = model.parameter_vector()
    b, c = p[1], p[2]
    z0 = np.array([min(np.roots([1, 0, 1, -x * b]), key=lambda root: abs(root.imag)).real for x in xs[0]])
    far = np.arange(POINTS) % 3 == 0                  # far off: one step leaves them 1e-8 away
    zs = np.vstack([z0, np.sin(z0) + c * times]) + np.where(far, 1e-4, 1e-9)
    calls = []
    original = polishing.newton_step

    def counted(model_):
        step = original(model_)
        return lambda xs_, zs_, p_, t_: (calls.append(len(t_)), step(xs_, zs_, p_, t_))[1]
    monkeypatch.setattr(polishing, "newton_step", counted)
    got = polish_algebraics(model, xs, zs, p, times)
    assert calls == [POINTS, int(far.sum())]
    expected = np.column_stack([newton_reference(model, xs[:, k], zs[:, k], p, times[k], 2 if far[k] else 1)
                                for k in range(POINTS)])
    np.testing.assert_allclose(got, expected, rtol=1e-14, atol=1e-300)


@pytest.mark.parametrize("fused_up_to", [4, 0])        # outputs and first step in one pass, or apart
def test_signals_that_do_not_depend_on_z_are_not_polished_and_the_others_are(monkeypatch, fused_up_to):
    monkeypatch.setattr(polishing, "FUSED_UP_TO", fused_up_to)
    model = small_model()
    xs, zs, times = points(model, 4)
    p = model.parameter_vector()
    # half of them near the solution (one step settles them), the others far off
    zs[:, ::2] = polish_algebraics(model, xs[:, ::2], zs[:, ::2], p, times[::2], 6) + 1e-9
    assert output_rows_function(model, [0, 1, 4, 5])[1] is False
    assert output_rows_function(model, [2])[1] is True
    plain = signals_at(model, xs, zs, p, times, [0, 1, 4, 5])
    np.testing.assert_array_equal(plain, evaluate_outputs(model, xs, zs, p, times, [0, 1, 4, 5]))
    polished = signals_at(model, xs, zs, p, times, [2, 3])
    z = polish_algebraics(model, xs, zs, p, times)
    np.testing.assert_array_equal(polished, evaluate_outputs(model, xs, z, p, times, [2, 3]))
    np.testing.assert_array_equal(polished[0], z[0])


def test_sparse_outputs_are_scattered_into_dense_rows():
    x, z, p, t = ca.SX.sym("x", 2), ca.SX.sym("z", 1), ca.SX.sym("p", 1), ca.SX.sym("t")
    sparse = ca.SX(4, 1)
    sparse[1], sparse[3] = x[0] * p, z * t
    function = ca.Function("sparse", [x, z, p, t], [sparse, ca.jacobian(ca.vertcat(x[0] * z, x[1]), x)])
    assert function.nnz_out(0) < function.numel_out(0) and function.nnz_out(1) < function.numel_out(1)
    rng = np.random.default_rng(5)
    xs, zs, times, pv = rng.normal(size=(2, POINTS)), rng.normal(size=(1, POINTS)), rng.normal(size=POINTS), [1.5]
    first, second = PointwiseEvaluator(function).evaluate(xs, zs, pv, times)
    assert first.shape == (4, POINTS) and second.shape == (4, POINTS)
    np.testing.assert_array_equal(first, one_by_one(ca.Function("f0", [x, z, p, t], [sparse]), xs, zs, pv, times))
    jac = ca.Function("f1", [x, z, p, t], [function(x, z, p, t)[1]])
    np.testing.assert_array_equal(second, one_by_one(jac, xs, zs, pv, times))


@pytest.mark.parametrize("n", [0, 1, BLOCK, BLOCK + 1])
def test_a_model_without_algebraic_unknowns_and_short_grids(n):
    model = small_model(nz=0)
    rng = np.random.default_rng(n)
    xs, zs, times = rng.normal(size=(2, n)), np.zeros((0, n)), np.linspace(0, 1, n)
    p = model.parameter_vector()
    got = signals_at(model, xs, zs, p, times)
    assert got.shape == (2, n)
    if n:
        np.testing.assert_array_equal(got, one_by_one(model.outputs, xs, zs, p, times))


def test_a_run_computes_only_the_signals_asked_for_with_the_same_values():
    model = small_model()
    full = simulate(model, 2.0, points=41, progress=False)
    asked = simulate(model, 2.0, points=41, progress=False, signals=["z1x1", "x0", "time", "x0"])
    assert asked.names == ["z1x1", "x0"]
    np.testing.assert_array_equal(asked.values, full.values[[3, 0]])
    again = simulate(model, 2.0, points=41, progress=False)          # IDAS objects reused: same run
    np.testing.assert_array_equal(again.values, full.values)
    with pytest.raises(ModelInputError, match="did you mean 'z1x1'"):
        simulate(model, 2.0, points=41, progress=False, signals=["z1x"])
    with pytest.raises(ModelInputError, match="list of names"):
        simulate(model, 2.0, points=41, progress=False, signals="x0")


def test_a_model_that_has_run_pickles_and_copies_without_its_derived_functions():
    model = small_model()
    first = simulate(model, 1.0, points=11, progress=False)
    for twin in (pickle.loads(pickle.dumps(model)), copy.deepcopy(model)):
        np.testing.assert_array_equal(simulate(twin, 1.0, points=11, progress=False).values, first.values)
