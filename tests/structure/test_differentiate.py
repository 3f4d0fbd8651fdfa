"""compiler.structure.differentiate.partial builds the very tree sympy.diff builds (the compiled
functions, and so the trajectories, must not change), only faster."""
from __future__ import annotations

import sympy
import pytest

from compiler.pipeline import flatten_spec
from compiler.structure import differentiate
from compiler.model.symbols import free_symbols
from compiler.structure.differentiate import partial
from compiler.structure.reduce import analyse

x, y, z, t = sympy.symbols("x y z t")
k = sympy.Symbol("k")

EXPRESSIONS = [
    x, 3 * x, x * y * z, 2 * (x + y) * z * x, x ** 2, x ** y, sympy.sqrt(x * y), 1 / (x + y),
    sympy.sin(x * y) * sympy.cos(x), sympy.atan2(y, x), sympy.exp(-x / k) * y, sympy.log(1 + x ** 2),
    sympy.tanh(x) - sympy.asin(y / 2), sympy.Abs(x) * y, sympy.sign(x - y), sympy.Min(x, y) + sympy.Max(x, 2),
    sympy.Piecewise((x ** 2, x > 0), (y, True)), sympy.Heaviside(x - 1) * y, x * sympy.oo + y,
    sympy.Function("f")(x, y), sympy.Function("g")(x * y) + x, sympy.floor(x) * x,
    sympy.cos(x) ** 2 * sympy.sin(y) ** 3 / (1 + z), (x + y) ** -2 * (x - y), 2.5 * x * t - sympy.Rational(3, 7) * y,
    (x + sympy.oo) * y * z, sympy.zoo * x * sympy.sin(y), 2.5 * x * sympy.exp(y * z) * sympy.atan2(z, t),
]


@pytest.mark.parametrize("expr", EXPRESSIONS, ids=str)
@pytest.mark.parametrize("symbol", [x, y, z, t])
def test_partial_is_the_tree_sympy_builds(expr, symbol):
    assert partial(expr, symbol) == sympy.diff(expr, symbol)
    assert free_symbols(expr) == expr.free_symbols


def test_memo_limit_clears_and_recomputes(monkeypatch):
    monkeypatch.setattr(differentiate, "_MEMO_LIMIT", 3)
    for expr in EXPRESSIONS:
        assert partial(expr, x) == sympy.diff(expr, x)
    assert len(differentiate._memo) <= 3 + 40


def test_every_partial_of_the_excavator_equals_sympy_diff():
    flat, _ = flatten_spec("MultibodyComponents.PlanarMechanics.examples.excavator.Excavator")
    system = analyse(flat).system             # index-reduced: includes differentiated equations
    pairs = [(e, s) for e in system.equations for s in e.free_symbols]
    assert len(pairs) > 1000
    assert all(partial(e, s) == sympy.diff(e, s) for e, s in pairs)


def test_free_symbols_memo_limit_clears_and_recomputes(monkeypatch):
    from compiler.model import symbols
    monkeypatch.setattr(symbols, "_MEMO_LIMIT", 3)
    for expr in EXPRESSIONS:
        assert free_symbols(expr) == expr.free_symbols
    assert len(symbols._free_memo) <= 3 + 40
