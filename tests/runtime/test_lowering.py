"""sympy -> CasADi lowering: every supported construct evaluates like sympy does, sharing is kept,
and unsupported input is a located DyadError."""
from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest
import sympy

from compiler.errors import DyadError
from compiler.model.flat import TIME
from compiler.lower.to_casadi import SXLowering, lower
from compiler.structure.reduced import Assignment, InitialProblem, ParameterInfo, ReducedSystem

a, b, c = sympy.symbols("a b c")


def lowered_value(expr, values: dict[str, float]) -> float:
    symbols = {name: ca.SX.sym(name) for name in values}
    walker = SXLowering(dict(symbols), "test")
    sx = walker.lower(expr)
    f = ca.Function("f", list(symbols.values()), [sx])
    return float(f(*values.values()))


POINT = {"a": 0.3, "b": -1.7, "c": 2.5}

CASES = [
    a + b * c, a - b / c, a * b * c / (a + c), -a, 2 * a / 3,
    a**2, a**3, a**-2, b**5, b**-3, c**17, c**-20, sympy.sqrt(c), 1 / sympy.sqrt(c), c**sympy.Rational(3, 2),
    c**sympy.Rational(-5, 2), c**sympy.Rational(1, 4), c**sympy.Rational(2, 3), c**a, sympy.E**a,
    sympy.sin(a), sympy.cos(b), sympy.tan(a), sympy.asin(a), sympy.acos(a), sympy.atan(b),
    sympy.atan2(a, b), sympy.atan2(b, -c), sympy.sinh(b), sympy.cosh(b), sympy.tanh(b),
    sympy.asinh(b), sympy.acosh(c), sympy.atanh(a), sympy.exp(b), sympy.log(c), sympy.log(c, 10),
    sympy.Abs(b), sympy.sign(b), sympy.sign(a), sympy.floor(b), sympy.ceiling(b),
    sympy.Min(a, b, c), sympy.Max(a, b, c), sympy.Min(sympy.Max(b, -1), 1),
    sympy.Heaviside(b), sympy.Heaviside(a), sympy.pi * a, sympy.E + a, sympy.Rational(7, 3) * a,
    sympy.Float(1.25e-3) * c, sympy.Mod(c, a), sympy.erf(a), sympy.cot(a), sympy.sec(a), sympy.csc(a),
    sympy.Piecewise((a, b > 0), (c, sympy.And(a > 0, c > 2)), (0, True)),
    sympy.Piecewise((a, sympy.Or(b > 0, c < 0)), (b, True)),
    sympy.Piecewise((a, sympy.Not(b >= 0)), (b, True)),
    sympy.Piecewise((1, sympy.Eq(a, 0.3)), (2, True)), sympy.Piecewise((1, sympy.Ne(a, 0.3)), (2, True)),
    sympy.Piecewise((1, a <= 0.3), (2, True)), sympy.Piecewise((1, a < 0.3), (2, True)),
]


@pytest.mark.parametrize("expr", CASES, ids=[str(e) for e in CASES])
def test_lowered_expression_matches_sympy(expr):
    expected = float(expr.subs({sympy.Symbol(k): v for k, v in POINT.items()}).evalf(30))
    assert lowered_value(expr, POINT) == pytest.approx(expected, rel=1e-13, abs=1e-15)


def test_heaviside_at_zero_uses_its_second_argument():
    assert lowered_value(sympy.Heaviside(a), {"a": 0.0}) == 0.5
    assert lowered_value(sympy.Heaviside(a, 1), {"a": 0.0}) == 1.0


def test_piecewise_without_a_true_branch_is_nan_where_nothing_applies():
    assert math.isnan(lowered_value(sympy.Piecewise((a, a > 1)), {"a": 0.0}))


def test_shared_subexpressions_stay_shared():
    inner = sympy.sin(a * b + sympy.cos(c))
    expr = sum(inner**k for k in range(1, 30))
    symbols = {n: ca.SX.sym(n) for n in "abc"}
    f = ca.Function("f", list(symbols.values()), [SXLowering(dict(symbols), "t").lower(expr)])
    # One sin, one cos, however many times the subexpression is used.
    assert f.n_instructions() < 200
    ops = [f.instruction_id(k) for k in range(f.n_instructions())]
    assert ops.count(ca.OP_SIN) == 1 and ops.count(ca.OP_COS) == 1


def test_deep_expression_does_not_recurse():
    expr = a
    for k in range(3000):
        expr = sympy.Add(sympy.sin(expr, evaluate=False), k, evaluate=False)   # 6000 levels
    assert math.isfinite(lowered_value(expr, {"a": 0.1}))


def _system(**overrides) -> ReducedSystem:
    x, z, k = sympy.symbols("x z k")
    fields = dict(name="M", states=["x"], ode=[-k * x], algebraics=["z"], alg=[z - x**2],
                  assignments=[], observables=[], parameters=[ParameterInfo("k", 2.0)],
                  initial=InitialProblem([z - x**2, x - 1], [None, None]), output_names=["x", "z"])
    fields.update(overrides)
    return ReducedSystem(**fields)


def test_unknown_symbol_is_a_dyad_error_naming_it():
    x = sympy.Symbol("x")
    with pytest.raises(DyadError, match="unknown symbol 'ghost'"):
        lower(_system(ode=[x * sympy.Symbol("ghost")]))


def test_unsupported_function_is_a_dyad_error_naming_it():
    x = sympy.Symbol("x")
    with pytest.raises(DyadError, match="gamma"):
        lower(_system(ode=[sympy.gamma(x)]))


def test_observables_are_not_visible_to_the_dae():
    x = sympy.Symbol("x")
    with pytest.raises(DyadError, match="unknown symbol 'obs'"):
        lower(_system(ode=[sympy.Symbol("obs")], observables=[Assignment("obs", 2 * x)]))


def test_unknown_output_name_is_an_error():
    with pytest.raises(DyadError, match="output 'nope'"):
        lower(_system(output_names=["x", "nope"]))


def test_functions_and_outputs_evaluate_assignments_time_and_derivatives():
    x, z, k = sympy.symbols("x z k")
    system = _system(assignments=[Assignment("w", k * TIME + x)],
                     ode=[-sympy.Symbol("w")], observables=[Assignment("o", sympy.Symbol("w") * z)],
                     output_names=["x", "z", "w", "o", "der(x)", "k"])
    model = lower(system)
    ode, alg = model.dae(3.0, 5.0, [2.0], 0.5)
    assert float(ode) == -(2.0 * 0.5 + 3.0) and float(alg) == 5.0 - 9.0
    values = np.asarray(model.outputs(3.0, 5.0, [2.0], 0.5)).ravel()
    assert values.tolist() == [3.0, 5.0, 4.0, 20.0, -4.0, 2.0]
    assert np.asarray(model.init(1.0, 1.0, [2.0], 0.0)).ravel().tolist() == [0.0, 0.0]
