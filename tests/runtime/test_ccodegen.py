"""C code generation: same numbers as the VM, cached by content, VM fallback without a compiler."""
from __future__ import annotations

import json
import os
import subprocess
import sys

import casadi as ca
import numpy as np
import pytest

from tests.runtime import runtime_systems as systems
from compiler import runtime
from compiler.lower import ccodegen
from compiler.lower.codegen import write_module
from compiler.lower.to_casadi import lower
from tests.runtime.lowered import compile_model

needs_cc = pytest.mark.skipif(ccodegen.find_compiler() is None, reason="no C compiler")


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("DYADC_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache"


@needs_cc
def test_c_model_matches_the_vm_and_is_cached(cache):
    vm = lower(systems.pendulum_cartesian(0.9))
    native = compile_model(systems.pendulum_cartesian(0.9), codegen="c")
    assert native.metadata["codegen"] == "c" and native.native_library.startswith(str(cache))
    # the code compared on one integrator (CasADi's IDAS; the C model's default is the native driver)
    for breakpoints in (None, [0.5, 1.0, 1.5]):          # one IDAS call, and segments
        a = runtime.simulate(vm, 2.0, rtol=1e-9, atol=1e-11, breakpoints=breakpoints, integrator="casadi")
        b = runtime.simulate(native, 2.0, rtol=1e-9, atol=1e-11, breakpoints=breakpoints, integrator="casadi")
        np.testing.assert_allclose(b.values, a.values, rtol=1e-9, atol=1e-11)
    libraries = list(cache.glob("*.so"))
    assert len(libraries) == 1
    mtime = libraries[0].stat().st_mtime_ns
    again = compile_model(systems.pendulum_cartesian(0.9), codegen="c")
    assert again.native_library == native.native_library
    assert libraries[0].stat().st_mtime_ns == mtime                 # reused, not rebuilt
    different = compile_model(systems.rc_circuit(), codegen="c")
    assert different.native_library != native.native_library


def test_missing_compiler_falls_back_to_the_vm_with_a_warning(cache, monkeypatch):
    monkeypatch.setattr(ccodegen, "find_compiler", lambda: None)
    with pytest.warns(ccodegen.CodegenWarning, match="no C compiler"):
        model = compile_model(systems.rc_circuit(), codegen="c")
    assert model.metadata["codegen"] == "vm" and model.native_library is None
    assert runtime.simulate(model, 0.1, points=3)["C.v"][-1] > 0


def test_failing_compiler_falls_back_to_the_vm(cache, monkeypatch, tmp_path):
    fake = tmp_path / "broken-cc"
    fake.write_text("#!/bin/sh\necho 'internal compiler error' >&2\nexit 1\n")
    fake.chmod(0o755)
    monkeypatch.setattr(ccodegen, "find_compiler", lambda: str(fake))
    with pytest.warns(ccodegen.CodegenWarning, match="internal compiler error"):
        model = compile_model(systems.rc_circuit(), codegen="c")
    assert model.native_library is None


@needs_cc
def test_generated_module_carries_its_native_library(cache, tmp_path):
    model = compile_model(systems.rc_circuit(), codegen="c")
    out = tmp_path / "gen"
    write_module(model, "rc_native", out)
    assert (out / "rc_native_dae.so").exists()
    code = ("import json, rc_native as m\n"
            "r = m.simulate(0.3, points=4, rtol=1e-9, atol=1e-12)\n"
            "print(json.dumps([m.model().native_library is not None, r['C.v'].tolist()]))")
    env = dict(os.environ, PYTHONPATH=str(out))
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                          cwd=out, timeout=120)
    assert done.returncode == 0, done.stderr
    uses_native, voltages = json.loads(done.stdout)
    assert uses_native
    np.testing.assert_allclose(voltages, 10 * (1 - np.exp(-np.linspace(0, 0.3, 4) / 0.1)),
                               atol=1e-7)


def test_the_c_jacobian_has_exact_x_and_z_blocks_and_no_t_or_p_blocks():
    model = lower(systems.pendulum_cartesian(0.9))
    dae = ccodegen.dae_function(model)
    jac = ccodegen.state_jacobian(dae)
    rng = np.random.default_rng(1)
    point = [0.4, rng.normal(size=dae.numel_in(1)), rng.normal(size=dae.numel_in(2)),
             np.array(model.parameter_defaults), np.zeros(0)]
    values = jac(*point, *dae(*point))
    full = dae.jacobian()(*point, *dae(*point))             # CasADi's own, every block
    for k in range(jac.n_out()):
        name = jac.name_out(k)
        assert name == dae.jacobian().name_out(k)              # the signature casadi.external expects
        if name.endswith(("_x", "_z")):
            np.testing.assert_allclose(np.array(values[k]), np.array(full[k]), rtol=1e-13, atol=1e-13)
        else:
            assert jac.sparsity_out(k).nnz() == 0
    assert any(dae.jacobian().sparsity_out(k).nnz() for k in range(jac.n_out())
               if jac.name_out(k).endswith("_p"))             # the pendulum does depend on p


@needs_cc
def test_a_large_jacobian_is_built_apart_into_the_same_library(tmp_path, monkeypatch):
    model = lower(systems.pendulum_cartesian(0.9))
    assert list(ccodegen.c_units(model)) == [ccodegen.SOURCE_NAME]          # small: one file
    monkeypatch.setattr(ccodegen, "SPLIT_FROM", 1)
    units = ccodegen.c_units(model)
    assert sorted(units) == ["dyad_functions.c", "dyad_jacobian.c"]
    assert "jac_dyad_dae" in units["dyad_jacobian.c"] and "jac_dyad_dae" not in units["dyad_functions.c"]
    folders = {kind: tmp_path / kind for kind in ("one", "two")}
    for folder in folders.values():
        folder.mkdir()
    one = model.with_native_library(ccodegen.compile_library(ccodegen.c_source(model),
                                                             ccodegen.find_compiler(), folders["one"]))
    two = model.with_native_library(ccodegen.compile_units(units, ccodegen.find_compiler(), folders["two"]))
    nx, nz, _ = model.sizes
    point = [0.3, np.linspace(0.1, 0.4, nx), np.linspace(-1.0, 1.0, nz),
             np.array(model.parameter_defaults), np.zeros(0)]
    for role in ("outputs", "polished_outputs"):
        assert (one.native_function(role) is None) == (two.native_function(role) is None)
    np.testing.assert_array_equal(np.array(two.native_dae()(*point)[1]), np.array(one.native_dae()(*point)[1]))
    jacobian = [ca.external("jac_dyad_dae", m.native_library) for m in (one, two)]
    outputs = [j(*point, *one.native_dae()(*point)) for j in jacobian]
    for a, b in zip(*outputs):
        np.testing.assert_array_equal(np.array(b), np.array(a))


def test_a_compiler_that_fails_on_one_file_fails_the_build_with_its_message(tmp_path):
    fake = tmp_path / "picky-cc"
    fake.write_text("#!/bin/sh\ncase \"$*\" in *jacobian*) echo 'jacobian too big' >&2; exit 1;; esac\n"
                    "exit 0\n")
    fake.chmod(0o755)
    with pytest.raises(RuntimeError, match="picky-cc failed: jacobian too big"):
        ccodegen.compile_units({"dyad_jacobian.c": "int a;", "dyad_functions.c": "int b;"}, str(fake), tmp_path)
