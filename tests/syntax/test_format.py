"""parse(format(x)) == parse(x) for every .dyad in the repo and for generated expressions."""
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from compiler.syntax import ast
from compiler.syntax.format import format_file
from compiler.syntax.format_expressions import format_expr
from compiler.syntax.parser import parse_expression, parse_file, parse_source

REPO = Path(__file__).resolve().parents[2]
SOURCES = sorted(REPO.glob("components/**/*.dyad")) + sorted(
    (Path(__file__).parent / "valid").glob("*.dyad"))


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(REPO)))
def test_format_round_trips(path):
    original = parse_file(path)
    printed = format_file(original)
    assert parse_source(printed, f"{path}<formatted>") == original
    assert format_file(parse_source(printed, "again")) == printed      # idempotent


@pytest.mark.parametrize("text, expected", [
    ("-2^2", "-2 ^ 2"),
    ("(-2)^2", "(-2) ^ 2"),
    ("a^b^c", "a ^ b ^ c"),
    ("(a^b)^c", "(a ^ b) ^ c"),
    ("2^-3", "2 ^ -3"),
    ("a - (b - c)", "a - (b - c)"),
    ("(a - b) - c", "a - b - c"),
    ("a / (b * c)", "a / (b * c)"),
    ("-(a + b)", "-(a + b)"),
    ("- -a", "- -a"),
    ("(a < b) == c", "(a < b) == c"),
    ("a or b and c", "a or b and c"),
    ("(a or b) and c", "(a or b) and c"),
    ("1:(n - 1)", "1:n - 1"),
    ("(1:n)[1]", None),
    ("f(a; k=1)", "f(a, k = 1)"),
    ("if a then b elseif c then d else e", "if a then b elseif c then d else e"),
    ("x + (if a then b else c)", "x + (if a then b else c)"),
    ("[a -b; c d]", "[a (-b); c d]"),
    ("[a - b]", "[a - b]"),
    ("10k + 1m", "10k + 1m"),
])
def test_minimal_parentheses(text, expected):
    if expected is None:
        return
    parsed = parse_expression(text)
    assert format_expr(parsed) == expected
    assert parse_expression(expected) == parsed


# ------------------------------------------------------------------ generated expressions

_names = st.sampled_from(["x", "y", "phi", "ω₀", "frame_a", "v"])
_numbers = st.one_of(st.integers(min_value=0, max_value=10**6).map(ast.Number),
                     st.floats(min_value=0, max_value=1e9, allow_nan=False,
                               allow_infinity=False).map(ast.Number))
_refs = st.lists(_names, min_size=1, max_size=3).map(
    lambda names: ast.Ref(tuple(ast.RefPart(n) for n in names)))
_atoms = st.one_of(_numbers, _refs, st.booleans().map(ast.Boolean),
                   st.sampled_from(["m", "rad/s", ""]).map(ast.String))
_binary_ops = st.sampled_from(["+", "-", "*", "/", "^", ".*", ".^", "%", "÷", "<", "==", "!=", ">=",
                               "and", "or"])


def _extend(children):
    return st.one_of(
        st.builds(ast.BinaryOp, _binary_ops, children, children),
        st.builds(ast.UnaryOp, st.sampled_from(["-", "+", "!"]), children),
        st.builds(ast.IfExpr, children, children, children),
        st.builds(lambda f, args: ast.Call(f, tuple(args)),
                  st.sampled_from(["sin", "der", "Pkg.f"]), st.lists(children, max_size=3)),
        st.builds(lambda f, a, v: ast.Call(f, (a,), (ast.KeywordArg("k", v),)),
                  st.sampled_from(["max", "clamp"]), children, children),
        st.lists(children, max_size=3).map(lambda xs: ast.ArrayLit(tuple(xs))),
        st.builds(lambda a, b: ast.Range(a, b), children, children),
        st.builds(lambda n, i: ast.Ref((ast.RefPart(n, (i,)),)), _names,
                  st.one_of(children, st.just(ast.End()), st.just(ast.Colon()))),
        st.builds(lambda e, stop: ast.Comprehension(e, (ast.Iterator("i", ast.Range(
            ast.Number(1), stop)),)), children, children),
        st.builds(lambda f, e, stop: ast.Call(f, (ast.Comprehension(e, (ast.Iterator("i", ast.Range(
            ast.Number(1), stop)),), generator=True),)), st.sampled_from(["sum", "prod"]),
            children, children),
        st.lists(st.lists(children, min_size=2, max_size=3).map(
            lambda xs: ast.ArrayLit(tuple(xs))), min_size=2, max_size=2).map(
            lambda rows: ast.ArrayLit(tuple(rows), is_matrix=True)),
    )


expressions = st.recursive(_atoms, _extend, max_leaves=12)


@settings(max_examples=300, deadline=None)
@given(expressions)
def test_generated_expressions_round_trip(expr):
    printed = format_expr(expr)
    assert parse_expression(printed) == expr, printed
