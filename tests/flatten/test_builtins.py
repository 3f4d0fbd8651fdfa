"""The one table of built-in functions (compiler/model/builtins.py): every entry evaluates, every
entry is what a misspelling of it suggests, and analyses use the same evaluator and guards."""
import math

import numpy as np
import pytest
import sympy

from compiler.errors import DyadError
from compiler.model.builtins import BUILTINS, builtin, suggest_function
from compiler.model.expressions import NOT_FOUND, EvalScope, Lexical, Mode, evaluate
from compiler.model.flat import der_name
from compiler.model.flatten import flatten_model
from compiler.model.library import Library
from compiler.syntax.parser import parse_expression

X = sympy.Symbol("x")

# One call of every entry and the value it gives (arrays as nested lists).
EXAMPLES = {
    "sin": ("sin(0)", 0), "cos": ("cos(0)", 1), "tan": ("tan(0)", 0),
    "asin": ("asin(1)", math.pi / 2), "acos": ("acos(1)", 0), "atan": ("atan(1)", math.pi / 4),
    "sinh": ("sinh(0)", 0), "cosh": ("cosh(0)", 1), "tanh": ("tanh(0)", 0),
    "exp": ("exp(0)", 1), "log": ("log(1)", 0), "log10": ("log10(100)", 2),
    "sqrt": ("sqrt(4)", 2), "abs": ("abs(-3)", 3), "sign": ("sign(-2)", -1),
    "floor": ("floor(2.5)", 2), "ceil": ("ceil(2.5)", 3), "atan2": ("atan2(1, 1)", math.pi / 4),
    "min": ("min(3, 1, 2)", 1), "max": ("max([1, 5], 3)", 5), "clamp": ("clamp(5, 0, 2)", 2),
    "norm": ("norm([3, 4])", 5), "dot": ("dot([1, 2], [3, 4])", 11), "sum": ("sum([1, 2, 3])", 6),
    "prod": ("prod([2, 3])", 6), "cross": ("cross([1, 0, 0], [0, 1, 0])", [0, 0, 1]),
    "transpose": ("transpose([1, 2])", [[1, 2]]), "length": ("length([1, 2, 3])", 3),
    "hcat": ("hcat([1, 2], [3, 4])", [[1, 3], [2, 4]]), "identity": ("identity(7)", 7),
    "mod": ("mod(-7, 3)", 2), "rem": ("rem(-7, 3)", -1), "div": ("div(7, 2)", 3),
    "not": ("not(1 > 2)", True), "der": ("der(x^2)", 2 * X * sympy.Symbol(der_name("x"))),
    "ifelse": ("ifelse(1 > 2, 1, 2)", 2), "zeros": ("zeros(2)", [0, 0]),
    "ones": ("ones(2, 1)", [[1], [1]]), "fill": ("fill(3, 2)", [3, 3]),
    "size": ("size([1, 2, 3])", [3]),
    "reshape": ("reshape([1, 2, 3, 4, 5, 6], 2, 3)", [[1, 3, 5], [2, 4, 6]]),
}
ALIAS_EXAMPLES = {"D": ("D(x^2)", "der(x^2)"), "minimum": ("minimum([4, 2, 8])", "min([4, 2, 8])"),
                  "maximum": ("maximum([1, 5, 3])", "max([1, 5, 3])")}


class _Model:
    """A scope node with one unknown, `x`."""
    path = "M"

    def member(self, name, mode, span):
        return X if name == "x" else NOT_FOUND

    def member_names(self):
        return ["x"]


class _Tracker:
    def is_unknown(self, name):
        return name == "x"

    def note_derivative(self, name):
        pass


def value(text: str):
    scope = EvalScope(_Model(), Lexical(Library(()), "", None), _Tracker())
    return evaluate(parse_expression(text), scope, Mode.SYMBOLIC)


def same(got, expected) -> bool:
    if isinstance(expected, list):
        return isinstance(got, np.ndarray) and got.shape == np.array(expected).shape and all(
            same(g, e) for g, e in zip(got.ravel(), np.array(expected, dtype=object).ravel()))
    if isinstance(expected, bool):
        return got is (sympy.true if expected else sympy.false)
    if isinstance(expected, sympy.Expr) and expected.free_symbols:
        return sympy.simplify(got - expected) == 0
    return math.isclose(float(got), expected, abs_tol=1e-12)


def test_every_entry_has_an_example():
    assert sorted(EXAMPLES) == sorted(BUILTINS)
    assert sorted(ALIAS_EXAMPLES) == sorted(a for entry in BUILTINS.values() for a in entry.aliases)


@pytest.mark.parametrize("name", sorted(BUILTINS))
def test_every_entry_evaluates(name):
    text, expected = EXAMPLES[name]
    assert same(value(text), expected), (text, value(text))


@pytest.mark.parametrize("alias", sorted(ALIAS_EXAMPLES))
def test_every_alias_means_its_entry(alias):
    text, meaning = ALIAS_EXAMPLES[alias]
    assert builtin(alias) is builtin(meaning.split("(")[0])
    assert sympy.simplify(value(text) - value(meaning)) == 0


@pytest.mark.parametrize("name", sorted(BUILTINS))
def test_a_misspelt_entry_suggests_it(name):
    assert suggest_function(name[0] + name) == name


@pytest.mark.parametrize("misspelt, suggested", [("maximun", "max"), ("modd", "mod"),
                                                 ("DD", "der"), ("ifels", "ifelse")])
def test_an_unknown_function_in_a_model_names_the_builtin(tmp_path, misspelt, suggested):
    path = tmp_path / "M.dyad"
    path.write_text(f"component M\n  variable y::Real\nrelations\n  y = {misspelt}(7, 3)\nend\n")
    with pytest.raises(DyadError) as caught:
        flatten_model(str(path))
    assert caught.value.message == f"unknown function `{misspelt}`"
    assert caught.value.hint == f"did you mean `{suggested}`?"
    assert (caught.value.span.line, caught.value.span.column) == (4, 7)


def test_reshape_keeps_the_number_of_elements():
    with pytest.raises(DyadError) as err:
        value("reshape([1, 2, 3], 2, 2)")
    assert "`reshape` cannot lay out 3 element(s) in sizes 2, 2 (4 elements)" in err.value.message
