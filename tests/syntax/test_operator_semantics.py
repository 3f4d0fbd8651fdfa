"""What the Dyad/Julia operators mean once flattened (compiler/model/expressions.py): the ternary is a
selection, `%` and rem() keep the dividend's sign, mod() the divisor's, `÷` and div() truncate,
D(x) is der(x), min/max reduce arrays, long chains become one flat sum."""
import math

import pytest
import sympy

from compiler.errors import DyadError
from compiler.model.flatten import flatten_model


def flatten(tmp_path, relations: str, declarations: str = ""):
    path = tmp_path / "M.dyad"
    path.write_text(f"component M\n{declarations}\nrelations\n{relations}\nend\n", encoding="utf-8")
    return flatten_model(str(path))


def value_of(tmp_path, expr: str, declarations: str = ""):
    """The value `y` takes from `y = expr` once flattened."""
    flat = flatten(tmp_path, f"  y = {expr}", f"{declarations}\n  variable y::Real")
    (residual,) = [e.residual for e in flat.equations]
    values = {p.name: p.value for p in flat.parameters if p.value is not None}
    residual = residual.subs({s: values[str(s)] for s in residual.free_symbols
                              if str(s) in values})
    (y,) = [s for s in residual.free_symbols if str(s) == "y"]
    return sympy.solve(residual, y)[0]


# Julia: 7.5 % 2 == 1.5, -7.5 % 2 == -1.5, mod(-7.5, 2) == 0.5, rem(7, -2) == 1,
# mod(7, -2) == -1, 7 ÷ 2 == 3, -7 ÷ 2 == -3, div(-7, -2) == 3.
@pytest.mark.parametrize("expr, value", [
    ("7.5 % 2", 1.5), ("-7.5 % 2", -1.5), ("rem(-7.5, 2)", -1.5), ("rem(7, -2)", 1),
    ("mod(-7.5, 2)", 0.5), ("mod(7, -2)", -1), ("mod(6, 3)", 0),
    ("7 ÷ 2", 3), ("-7 ÷ 2", -3), ("div(-7, -2)", 3), ("div(7.9, 1)", 7),
    ("2 + 7 % 4 * 2", 8), ("maximum([1, 5, 3])", 5), ("minimum([4, 2, 8])", 2),
    ("max([1, 9], 3)", 9), ("true ? 1 : 2", 1), ("1 > 2 ? 1 : 2", 2),
])
def test_values(tmp_path, expr, value):
    assert math.isclose(float(value_of(tmp_path, expr)), value, abs_tol=1e-12)
    # the same through a parameter default, evaluated numerically
    assert math.isclose(float(value_of(tmp_path, "p", f"  parameter p::Real = {expr}")), value,
                        abs_tol=1e-12)


@pytest.mark.parametrize("expr, what", [("5 % 0", "`rem` by zero"), ("mod(1, 0)", "`mod` by zero"),
                                        ("[1, 2] % 2", "`rem` needs scalars"),
                                        ("rem(1)", "`rem` takes two arguments")])
def test_integer_operator_errors_are_located(tmp_path, expr, what):
    with pytest.raises(DyadError) as caught:
        value_of(tmp_path, expr)
    assert what in caught.value.message and caught.value.span.line == 5


def test_ternary_on_a_variable_is_a_piecewise_selection(tmp_path):
    flat = flatten(tmp_path, "  y = x > 0 ? x : -x\n  der(x) = 1",
                   "  variable x::Real\n  variable y::Real")
    (selection,) = [e.residual for e in flat.equations if e.residual.has(sympy.Piecewise)]
    assert selection.atoms(sympy.Piecewise)


def test_capital_d_is_der(tmp_path):
    with_d = flatten(tmp_path, "  D(x) = -x", "  variable x::Real")
    with_der = flatten(tmp_path, "  der(x) = -x", "  variable x::Real")
    assert [str(e.residual) for e in with_d.equations] == \
        [str(e.residual) for e in with_der.equations]
    assert with_d.derivatives == with_der.derivatives != {}


def test_remainder_of_a_variable_stays_symbolic_with_floor(tmp_path):
    flat = flatten(tmp_path, "  y = x % 2\n  der(x) = 1", "  variable x::Real\n  variable y::Real")
    (residual,) = [e.residual for e in flat.equations if e.residual.has(sympy.floor)]
    x = next(s for s in residual.free_symbols if str(s) == "x")
    y = next(s for s in residual.free_symbols if str(s) == "y")
    solved = sympy.solve(residual, y)[0]
    assert float(solved.subs(x, -7.5)) == -1.5 and float(solved.subs(x, 7.5)) == 1.5


def test_long_sum_flattens_to_one_flat_add(tmp_path):
    terms = " + ".join(f"{i % 5 + 1} * x" for i in range(3000)) + " - x"
    flat = flatten(tmp_path, f"  y = {terms}\n  der(x) = 1", "  variable x::Real\n  variable y::Real")
    (residual,) = [e.residual for e in flat.equations if "y" in str(e.residual)]
    x = next(s for s in residual.free_symbols if str(s) == "x")
    y = next(s for s in residual.free_symbols if str(s) == "y")
    expected = sum(i % 5 + 1 for i in range(3000)) - 1
    assert sympy.expand(residual - (y - expected * x)) == 0


@pytest.mark.filterwarnings("error")      # the unit check walks the chains too (it used to overflow)
def test_long_products_and_logic_chains(tmp_path):
    factors = " * ".join(["1.001"] * 2000) + " / 1.001"
    assert math.isclose(float(value_of(tmp_path, factors)), 1.001 ** 1999, rel_tol=1e-12)
    logic = " and ".join(["x < 5"] * 2000) + " or x > 9"
    selection = value_of(tmp_path, f"{logic} ? 1 : 0", "  variable x::Real")
    x = next(s for s in selection.free_symbols if str(s) == "x")
    assert selection.subs(x, 3) == 1 and selection.subs(x, 7) == 0 and selection.subs(x, 10) == 1
