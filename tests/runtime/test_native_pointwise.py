"""`--codegen c`: the outputs and the polishing of the algebraic unknowns run from the model's C
library (compiler/lower/ccodegen.py pointwise_functions) and give the VM's numbers to round-off;
a library built before it held them leaves those evaluations on the VM."""
from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from tests.runtime import runtime_systems as systems
from tests.runtime.test_outputs_vectorized import points, small_model
from compiler import runtime
from compiler.cache import c_code, c_libraries
from compiler.lower import ccodegen
from compiler.lower.to_casadi import lower
from compiler.runtime import outputs, polishing

pytestmark = pytest.mark.skipif(ccodegen.find_compiler() is None, reason="no C compiler")
ROUND_OFF = dict(rtol=1e-12, atol=1e-14)


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("DYADC_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache"


def native(model: runtime.CompiledModel) -> runtime.CompiledModel:
    compiled = c_code.compile_c(model)
    assert compiled.metadata["codegen"] == "c"
    return compiled


def test_the_library_holds_the_outputs_at_polished_z(cache):
    vm = small_model()
    c = native(vm)
    # two algebraic unknowns: one function of the Newton step and the outputs at its result
    assert c.native_function("polished_outputs") is not None and vm.native_function("polished_outputs") is None
    for role in ("outputs", "algebraic_newton", "algebraic_residual"):
        assert c.native_function(role) is None, role
    xs, zs, times = points(vm, 3)
    p = vm.parameter_vector()
    expected = polishing.polished_outputs_function(vm, None)
    for k in (0, 17, len(times) - 1):
        args = (xs[:, k], zs[:, k], p, times[k])
        for got, value in zip(c.native_function("polished_outputs")(*args), expected(*args)):
            np.testing.assert_allclose(np.asarray(got), np.asarray(value), **ROUND_OFF)


def test_other_algebraic_systems_get_the_outputs_and_the_newton_function_and_residual(monkeypatch):
    """Above FUSED_UP_TO unknowns the step is solved by numpy from these two functions; without
    algebraic unknowns there is nothing to polish."""
    names = runtime.CompiledModel.NATIVE_FUNCTION_NAMES
    vm = small_model()
    assert [f.name() for f in ccodegen.pointwise_functions(vm)] == [names["polished_outputs"]]
    assert [f.name() for f in ccodegen.pointwise_functions(small_model(nz=0))] == [names["outputs"]]
    monkeypatch.setattr(polishing, "FUSED_UP_TO", 1)
    functions = ccodegen.pointwise_functions(vm)
    assert [f.name() for f in functions] == [names[r] for r in ("outputs", "algebraic_newton", "algebraic_residual")]
    xs, zs, times = points(vm, 3)
    p = vm.parameter_vector()
    r, jac = functions[1](xs[:, 0], zs[:, 0], p, times[0])
    r_vm, jac_vm = vm.algebraic_newton()(xs[:, 0], zs[:, 0], p, times[0])
    np.testing.assert_allclose(np.asarray(r), np.asarray(r_vm), **ROUND_OFF)
    np.testing.assert_allclose(np.asarray(ca.densify(jac)), np.asarray(ca.densify(jac_vm)), **ROUND_OFF)
    np.testing.assert_allclose(np.asarray(functions[0](xs[:, 0], zs[:, 0], p, times[0])),
                               np.asarray(vm.outputs(xs[:, 0], zs[:, 0], p, times[0])), **ROUND_OFF)


def test_polished_outputs_in_c_equal_the_vm_ones(cache):
    vm = small_model()
    c = native(vm)
    xs, zs, times = points(vm, 4)
    zs = zs * 0.01 + 0.3                  # near the algebraic solution: Newton converges
    p = vm.parameter_vector()
    z_vm = outputs.polish_algebraics(vm, xs, zs, p, times)
    z_c = outputs.polish_algebraics(c, xs, zs, p, times)
    assert not np.allclose(z_vm, zs)      # polishing moved them
    np.testing.assert_allclose(z_c, z_vm, **ROUND_OFF)
    np.testing.assert_allclose(outputs.signals_at(c, xs, zs, p, times),
                               outputs.signals_at(vm, xs, zs, p, times), **ROUND_OFF)
    assert ("evaluator", "polished_outputs", "native") in c._derived        # the C function did the work
    # outputs at z as given: the VM's function (the library holds only those at polished z)
    np.testing.assert_array_equal(outputs.evaluate_outputs(c, xs, zs, p, times),
                                  outputs.evaluate_outputs(vm, xs, zs, p, times))


def test_rows_that_do_not_depend_on_z_may_come_from_the_outputs_at_polished_z(cache, monkeypatch):
    monkeypatch.setattr(outputs, "CHEAPER_IN_C", 1e9)       # C whenever it has a function for them
    vm = small_model()
    c = native(vm)
    xs, zs, times = points(vm, 7)
    p = vm.parameter_vector()
    free = [0, 1, 4, 5]                   # x0, x0 * x1, exp(-a t), 2.5
    np.testing.assert_allclose(outputs.evaluate_outputs(c, xs, zs, p, times, free),
                               outputs.evaluate_outputs(vm, xs, zs, p, times, free), **ROUND_OFF)
    assert ("evaluator", "polished_outputs", "native") in c._derived
    with_z = [2, 3]                       # at z as given: only the VM has them
    np.testing.assert_array_equal(outputs.evaluate_outputs(c, xs, zs, p, times, with_z),
                                  outputs.evaluate_outputs(vm, xs, zs, p, times, with_z))


@pytest.mark.parametrize("cheaper_in_c", [0.0, 1e9])       # the VM's subset, and rows of C's all
def test_asked_rows_equal_the_vm_ones_either_way(cache, monkeypatch, cheaper_in_c):
    monkeypatch.setattr(outputs, "CHEAPER_IN_C", cheaper_in_c)
    vm = small_model()
    c = native(vm)
    xs, zs, times = points(vm, 5)
    zs = zs * 0.01 + 0.3
    p = np.repeat(vm.parameter_vector().reshape(-1, 1), len(times), axis=1)
    p[0, 100:] *= 1.5                     # two runs of parameters
    rows = [3, 0, 4]                      # z1 * x1 + t depends on z: polished
    got = outputs.signals_at(c, xs, zs, p, times, rows)
    np.testing.assert_allclose(got, outputs.signals_at(vm, xs, zs, p, times, rows), **ROUND_OFF)
    assert (("evaluator", "polished_outputs", "native") in c._derived) == (cheaper_in_c > 1)
    assert outputs.signals_at(c, xs, zs, p, times, []).shape == (0, len(times))


def test_a_simulation_in_c_reports_the_vm_values(cache):
    vm = lower(systems.pendulum_cartesian(0.9))
    c = native(vm)
    fused = len(c.algebraic_names) <= polishing.FUSED_UP_TO
    assert c.algebraic_names and c.native_function("polished_outputs" if fused else "algebraic_newton") is not None
    # the code compared on one integrator (CasADi's IDAS; the C model's default is the native driver)
    a = runtime.simulate(vm, 2.0, points=301, rtol=1e-10, atol=1e-12, integrator="casadi")
    b = runtime.simulate(c, 2.0, points=301, rtol=1e-10, atol=1e-12, integrator="casadi")
    # the integrator's Jacobian differs in round-off between C and the VM, so the trajectories
    # do too (to the tolerance); the outputs of the same (x, z) agree to round-off
    np.testing.assert_allclose(b.values, a.values, rtol=1e-8, atol=1e-9)
    p = vm.parameter_vector()
    xs = np.vstack([b[name] for name in vm.state_names])
    zs = np.vstack([b[name] for name in vm.algebraic_names]) * (1 + 1e-7)      # off the equations
    np.testing.assert_allclose(outputs.signals_at(c, xs, zs, p, b.time),
                               outputs.signals_at(vm, xs, zs, p, b.time), **ROUND_OFF)


def test_a_library_without_the_pointwise_functions_leaves_them_on_the_vm(tmp_path):
    """A library built by an earlier dyadc (only the DAE and its Jacobian) still runs the model."""
    vm = small_model()
    dae = ccodegen.dae_function(vm)
    with tempfile.TemporaryDirectory() as scratch:
        generator = ca.CodeGenerator("dyad_dae", {"with_header": False})
        generator.add(dae)
        generator.add(ccodegen.state_jacobian(dae))
        generator.generate(scratch + os.sep)
        source = (Path(scratch) / "dyad_dae.c").read_text()
    library = c_code.build_library(source, ccodegen.find_compiler(), tmp_path / "old")
    old = vm.with_native_library(library)
    assert old.native_dae() is not None and old.native_function("outputs") is None
    xs, zs, times = points(vm, 6)
    p = vm.parameter_vector()
    np.testing.assert_array_equal(outputs.signals_at(old, xs, zs, p, times),
                                  outputs.signals_at(vm, xs, zs, p, times))


def test_an_entry_from_before_the_pointwise_functions_is_not_reused(tmp_path):
    """A cached model links to its library's entry (compiler/cache/native.py); an entry written
    when libraries held only the DAE (format 1) must fail validation, so that it is rebuilt."""
    folder, key = tmp_path / "c", "0123456789abcdef0123456789abcdef"

    def build(scratch):
        (scratch / "lib.so").write_bytes(b"\x7fELF not really")
        return scratch / "lib.so"
    library, built = c_libraries.fetch_or_build(folder, key, build)
    assert built and c_libraries.valid_entry(folder, key) == library
    record = folder / f"dyad_{key}.json"
    old = json.loads(record.read_text())
    record.write_text(json.dumps({**old, "format": 1}))
    assert c_libraries.valid_entry(folder, key) is None
