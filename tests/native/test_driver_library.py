"""The native IDAS driver library (compiler/runtime/native) loads and integrates closed-form problems to
their exact answers: an ODE (exponential decay) and an index-1 DAE (an oscillator whose force is
an algebraic unknown), through the same C functions dyadc generates for a model."""
from __future__ import annotations

import os
import subprocess
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from compiler.lower import ccodegen
from compiler.runtime.native import library

pytestmark = pytest.mark.skipif(library.driver_library()[0] is None,
                                reason="native IDAS driver not built (make install builds it)")


def model_library(folder: Path, ode, alg, x, z, p) -> Path:
    """dyad_dae and jac_dyad_dae of (ode, alg) compiled as dyadc compiles a model's."""
    t, u = ca.SX.sym("t"), ca.SX.sym("u", 0)
    dae = ca.Function("dyad_dae", [t, x, z, p, u], [ode, alg, ca.SX(0, 1), ca.SX(0, 1)],
                      ca.dyn_in(), ca.dyn_out())
    generator = ca.CodeGenerator("dyad_dae", {"with_header": False})
    generator.add(dae)
    generator.add(ccodegen.state_jacobian(dae))
    generator.generate(str(folder) + os.sep)
    subprocess.run(["gcc", "-O1", "-fPIC", "-shared", "dyad_dae.c", "-o", "dyad_dae.so", "-lm"],
                   cwd=folder, check=True)
    return folder / "dyad_dae.so"


def integrate(path: Path, nx: int, nz: int, p, x0, z0, times, rtol=1e-10):
    driver = library.Driver(str(path), nx, nz, len(p), 0)
    none = np.zeros(0, np.intc)
    assert driver.setup(rtol, np.full(nx + nz, 1e-12), False, 0.0, 0, none, none, none, 0.0) == 0
    assert driver.restart(0.0, x0, z0, p, np.zeros(0, np.intc), 0.0) == 0
    flag, done, xs, zs, t, x, z, _, _ = driver.advance(times[-1], times, np.full(nx, 1e300), 100000)
    assert (flag, done, t) == (library.REACHED, len(times), times[-1])
    return xs, zs, driver.counters()


def test_exponential_decay(tmp_path):
    x, k = ca.SX.sym("x", 1), ca.SX.sym("k", 1)
    path = model_library(tmp_path, -k * x, ca.SX(0, 1), x, ca.SX.sym("z", 0), k)
    times = np.linspace(0.1, 2.0, 20)
    xs, _, counters = integrate(path, 1, 0, [3.0], [2.0], [], times)
    assert np.max(np.abs(xs[0] - 2.0 * np.exp(-3.0 * times))) < 1e-8
    assert counters[0] > 10                 # IDAS took steps, counted where IDAS counts them


def test_oscillator_with_an_algebraic_force(tmp_path):
    """x' = v, v' = -f, 0 = f - w^2 x: x = cos(w t), f = w^2 cos(w t)."""
    x, f, w = ca.SX.sym("x", 2), ca.SX.sym("f", 1), ca.SX.sym("w", 1)
    path = model_library(tmp_path, ca.vertcat(x[1], -f), f - w ** 2 * x[0], x, f, w)
    times = np.linspace(0.25, 5.0, 20)
    xs, zs, _ = integrate(path, 2, 1, [2.0], [1.0, 0.0], [4.0], times)
    assert np.max(np.abs(xs[0] - np.cos(2.0 * times))) < 1e-7
    assert np.max(np.abs(zs[0] - 4.0 * np.cos(2.0 * times))) < 4e-7


def test_a_missing_model_function_is_an_error_that_names_it(tmp_path):
    (tmp_path / "empty.c").write_text("int nothing(void) { return 0; }\n")
    subprocess.run(["gcc", "-fPIC", "-shared", "empty.c", "-o", "empty.so"], cwd=tmp_path, check=True)
    with pytest.raises(RuntimeError, match="no function dyad_dae"):
        library.Driver(str(tmp_path / "empty.so"), 1, 0, 0, 0)


def test_the_sundials_version_is_the_one_fetched():
    from compiler.native.build import SUNDIALS_VERSION
    assert library.sundials_version() == ".".join(map(str, SUNDIALS_VERSION))


def test_the_algebraic_equations_are_solved_to_round_off_in_c(tmp_path):
    """A point on a circle of radius L at x and its slope b = -x / a, from a guess 10% off
    (the restart point of a state-set switch); z is left alone where the Jacobian is singular,
    and no real root is not called converged."""
    x, z, radius = ca.SX.sym("x", 1), ca.SX.sym("z", 2), ca.SX.sym("L", 1)
    alg = ca.vertcat(z[0] ** 2 + x ** 2 - radius ** 2, z[0] * z[1] + x)
    path = model_library(tmp_path, ca.SX(0.0), alg, x, z, radius)
    driver = library.Driver(str(path), 1, 2, 1, 0)
    outcome, solved = driver.solve_algebraic(0.0, [0.6], [0.88, -0.66], [1.0], 8)
    assert outcome == 1
    np.testing.assert_allclose(solved, [0.8, -0.75], rtol=0, atol=2e-16)
    outcome, solved = driver.solve_algebraic(0.0, [0.6], [0.0, 0.0], [1.0], 8)
    assert (outcome, list(solved)) == (-1, [0.0, 0.0])         # d(alg)/dz singular at z = 0
    outcome, _ = driver.solve_algebraic(0.0, [2.0], [0.5, 1.0], [1.0], 8)
    assert outcome == 0                                        # no real z: a^2 = 1 - 4
