"""Interpolation of tabulated data (compiler/model/interpolation.py, datasets.py, object_values.py):
the interpolants against closed forms, then whole models of tests/library/interpolation/Signals.dyad
run on the VM, in C and as a generated module, against the exact values and integrals."""
from __future__ import annotations

import math
import shutil
from pathlib import Path

import casadi as ca
import numpy as np
import pytest
import sympy

from compiler import runtime
from compiler.api import simulate
from compiler.cache.c_code import compile_c, on_vm
from compiler.lower import ccodegen
from compiler.lower.codegen import write_module
from compiler.model import interpolation
from compiler.julia.rewrite import translate
from compiler.model.ranges import float_range
from compiler.pipeline import compile_spec

FIXTURE = Path(__file__).parent / "interpolation" / "Signals.dyad"
GRID = [k / 10 for k in range(11)]               # 0:0.1:1 as Julia gives it
SQUARED = "squared(r) = @. ^(r, 2)\n"             # a package helper in Julia, read by dyadc
TIGHT = dict(rtol=1e-10, atol=1e-12)


def chord_of_square(t: float) -> float:
    """The linear interpolation of t^2 between the samples 0, 0.1, ..., 1 (extended beyond)."""
    a = min(max(math.floor(t * 10 + 1e-9), 0), 9) / 10
    return a * a + (2 * a + 0.1) * (t - a)


def project(tmp_path: Path) -> tuple[Path, Path]:
    """Signals/dyad/Signals.dyad, Signals/src/helpers.jl, Signals/test/data/samples.csv, and a
    library folder linking Signals to its dyad/ folder."""
    root = tmp_path / "Signals"
    (root / "dyad").mkdir(parents=True)
    (root / "src").mkdir()
    (root / "test" / "data").mkdir(parents=True)
    shutil.copy(FIXTURE, root / "dyad" / "Signals.dyad")
    (root / "src" / "helpers.jl").write_text(SQUARED, encoding="utf-8")
    rows = "\n".join(f"{t!r},{t * t!r},unused" for t in GRID)
    (root / "test" / "data" / "samples.csv").write_text(f"time_s,value,note\n{rows}\n",
                                                         encoding="utf-8")
    lib = tmp_path / "lib"
    lib.mkdir()
    (lib / "Signals").symlink_to(root / "dyad", target_is_directory=True)
    return root / "dyad" / "Signals.dyad", lib


# ------------------------------------------------------------------------- the interpolants

def test_linear_interpolation_is_exact_at_the_samples_and_the_chord_between():
    table = interpolation.linear([t * t for t in GRID], GRID, "t^2")
    for t in GRID:
        assert table.value(t) == t * t
    for t in np.linspace(-0.2, 1.3, 301):
        assert table.value(t) == pytest.approx(chord_of_square(t), abs=1e-15)
    slope = table.derivative()
    assert slope.value(0.25) == pytest.approx(0.5) and slope.value(0.95) == pytest.approx(1.9)
    assert slope.derivative() is None                       # straight pieces: no curvature


def test_quadratic_interpolation_reproduces_a_parabola_everywhere():
    times = [0.0, 0.3, 0.5, 1.1, 1.6, 2.0]
    parabola = lambda t: 3 - 2 * t + 0.5 * t * t              # noqa: E731
    table = interpolation.quadratic([parabola(t) for t in times], times, "q")
    for t in np.linspace(-0.5, 2.5, 121):
        assert table.value(t) == pytest.approx(parabola(t), abs=1e-12)
        assert table.derivative().value(t) == pytest.approx(-2 + t, abs=1e-12)


def test_quadratic_interpolation_uses_the_forward_three_samples():
    # on [t1, t2) the parabola through samples 1, 2, 3; the last interval reuses the one before
    times, values = [0.0, 1.0, 2.0, 3.0], [0.0, 1.0, 0.0, 5.0]
    table = interpolation.quadratic(values, times, "zigzag")
    through_first = lambda t: t * (2 - t)                    # noqa: E731  samples 0, 1, 2
    through_second = lambda t: 1 - (t - 1) + 3 * (t - 1) * (t - 2)   # noqa: E731  samples 1, 2, 3
    assert table.value(0.5) == pytest.approx(through_first(0.5))
    assert table.value(1.5) == pytest.approx(through_second(1.5))
    assert table.value(2.5) == pytest.approx(through_second(2.5))


def test_constant_interpolation_holds_the_last_sample():
    table = interpolation.constant([1.0, -2.0, 0.5], [0.0, 1.0, 2.0], "steps")
    assert [table.value(t) for t in (-1, 0, 0.999, 1, 1.5, 2, 7)] == [1, 1, 1, -2, -2, 0.5, 0.5]
    assert table.derivative() is None


def test_cubic_spline_is_the_natural_spline():
    scipy_interpolate = pytest.importorskip("scipy.interpolate")
    times = [0.0, 0.4, 1.0, 1.3, 2.2, 3.0]
    values = [1.0, -0.5, 2.0, 0.3, 0.0, 1.7]
    table = interpolation.cubic_spline(values, times, "spline")
    reference = scipy_interpolate.CubicSpline(times, values, bc_type="natural")
    for t in np.linspace(0, 3, 97):
        assert table.value(t) == pytest.approx(float(reference(t)), abs=1e-12)
        assert table.derivative().value(t) == pytest.approx(float(reference(t, 1)), abs=1e-11)


def test_the_casadi_form_gives_the_same_numbers_and_exact_derivatives():
    table = interpolation.quadratic([math.sin(t) for t in GRID], GRID, "sine")
    x = ca.SX.sym("x")
    value = table.evaluate(x, ca.if_else)
    f = ca.Function("f", [x], [value, ca.jacobian(value, x)])
    for t in (-0.05, 0.0, 0.15, 0.5, 0.9, 1.0, 1.2):
        y, dy = (float(v) for v in f(t))
        assert y == table.value(t)
        assert dy == pytest.approx(table.derivative().value(t), rel=1e-13)


@pytest.mark.parametrize("build, data, message", [
    (interpolation.linear, ([1.0], [0.0]), "at least 2 samples"),
    (interpolation.quadratic, ([1.0, 2.0], [0.0, 1.0]), "at least 3 samples"),
    (interpolation.linear, ([1.0, 2.0, 3.0], [0.0, 1.0, 1.0]), "strictly increasing"),
    (interpolation.constant, ([1.0, 2.0], [0.0]), "as many values as times"),
])
def test_unusable_data_is_refused(build, data, message):
    with pytest.raises(interpolation.InterpolationError, match=message):
        build(*data, "bad")


def test_an_interpolant_in_sympy_differentiates_and_evaluates_exactly():
    table = interpolation.linear([t * t for t in GRID], GRID, "t^2")
    u = sympy.Symbol("u")
    applied = interpolation.function(table, "look")(u)
    assert sympy.diff(applied, u).subs(u, sympy.Float(0.25)) == pytest.approx(0.5)
    assert applied.subs(u, sympy.Float(0.3)) == pytest.approx(0.09, abs=1e-16)
    hold = interpolation.function(interpolation.constant([1.0, 2.0], [0.0, 1.0], "h"), "h")(u)
    assert sympy.diff(hold, u) == 0


def test_float_ranges_are_julias_and_julia_helpers_are_translated():
    values = [float(v) for v in float_range(sympy.Integer(0), sympy.Float(0.1), sympy.Integer(1), None)]
    assert values == GRID                                   # 0.3, not 0.30000000000000004
    assert len(float_range(sympy.Float(0.5), None, sympy.Float(3.2), None)) == 3
    assert translate("@. ^(r, 2)").strip() == "((r) .^ (2))"
    assert translate("@. a*x - -b + 1e-3").strip() == "a.*x .- -b .+ 1e-3"
    assert translate("-(x) + *(a, b, c)") == "-(x) + ((a) * (b) * (c))"


# ----------------------------------------------------------------------------- whole models

def test_linear_table_follows_the_chord_and_integrates_to_its_area(tmp_path):
    model, lib = project(tmp_path)
    result = simulate(f"{model}:SquareChord", stop=1.0, lib_dirs=[str(lib)], points=201, **TIGHT)
    for t, y in zip(result.time, result["y"]):
        assert y == pytest.approx(chord_of_square(t), abs=1e-13)
    # the trapezoids of t^2 on a 0.1 grid: 1/3 + 0.1^2 / 6
    assert result["area"][-1] == pytest.approx(1 / 3 + 0.01 / 6, abs=1e-9)


def test_quadratic_table_integrates_a_parabola_exactly(tmp_path):
    model, lib = project(tmp_path)
    result = simulate(f"{model}:Parabola", stop=2.0, lib_dirs=[str(lib)], **TIGHT)
    times = np.asarray(result.time)
    np.testing.assert_allclose(result["y"], 3 - 2 * times + 0.5 * times ** 2, atol=1e-12)
    assert result["area"][-1] == pytest.approx(6 - 4 + 8 / 6, abs=1e-9)


def test_a_csv_dataset_beside_the_package_gives_the_same_signal(tmp_path):
    model, lib = project(tmp_path)
    from_file = simulate(f"{model}:FromFile", stop=1.0, lib_dirs=[str(lib)], points=101, **TIGHT)
    table = simulate(f"{model}:SquareChord", stop=1.0, lib_dirs=[str(lib)], points=101, **TIGHT)
    np.testing.assert_allclose(from_file["y"], table["y"], atol=1e-15)
    assert from_file["area"][-1] == pytest.approx(1 / 3 + 0.01 / 6, abs=1e-9)


def test_a_hold_integrates_to_the_area_of_its_steps(tmp_path):
    model, lib = project(tmp_path)
    result = simulate(f"{model}:Staircase", stop=3.5, lib_dirs=[str(lib)], **TIGHT)
    assert result["area"][-1] == pytest.approx(1 - 2 + 0.5 + 4 * 0.5, abs=1e-6)


@pytest.mark.skipif(ccodegen.find_compiler() is None, reason="no C compiler")
def test_generated_c_and_python_modules_compute_the_same_numbers(tmp_path):
    model, lib = project(tmp_path)
    compiled = compile_spec(f"{model}:Parabola", [str(lib)]).model
    # the code compared on one integrator (CasADi's IDAS; the C model's default is the native driver)
    vm = runtime.simulate(on_vm(compiled), 2.0, **TIGHT, integrator="casadi")
    native = compile_c(compiled, tmp_path / "c")
    assert native.metadata["codegen"] == "c"
    in_c = runtime.simulate(native, 2.0, **TIGHT, integrator="casadi")
    np.testing.assert_allclose(in_c.values, vm.values, rtol=1e-12, atol=1e-14)
    # the module written without C builds it on its first run: the compiler's own default run
    path = write_module(compiled, "parabola", tmp_path / "module")
    namespace: dict = {}
    exec(compile(path.read_text(encoding="utf-8"), str(path), "exec"), namespace)
    generated = namespace["simulate"](2.0, **TIGHT)
    reference = runtime.simulate(compiled, 2.0, **TIGHT)
    assert generated.stats["codegen"] == reference.stats["codegen"] == "c"
    assert generated.stats["integrator"] == reference.stats["integrator"]
    assert (generated.values == reference.values).all()


def test_an_interpolator_built_from_values_and_times(tmp_path):
    scipy_interpolate = pytest.importorskip("scipy.interpolate")
    model, lib = project(tmp_path)
    result = simulate(f"{model}:Spline", stop=3.0, lib_dirs=[str(lib)], points=61, **TIGHT)
    reference = scipy_interpolate.CubicSpline([0, 1, 2, 3], [1, 3, 2, 5], bc_type="natural")
    np.testing.assert_allclose(result["y"], reference(np.asarray(result.time)), atol=1e-12)
