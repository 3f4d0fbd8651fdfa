"""Deep or huge input (issue 19, item 6): never an internal RecursionError. Nesting beyond the
limit is a located "nested too deeply" error; long chains (sums, products, `and`) just work; a
number literal is exact or a located error."""
import subprocess
import sys
from pathlib import Path

import pytest

from compiler.errors import DyadError
from compiler.syntax import ast
from compiler.syntax.format import format_file
from compiler.syntax.parser import parse_expression, parse_source
from compiler.syntax.transformer import MAX_NESTING

REPO = Path(__file__).resolve().parents[2]


def model(rhs: str) -> str:
    return f"component Deep\n  variable x::Real\nrelations\n  x = {rhs}\nend\n"


def nested(template: str, depth: int, inner: str = "x") -> str:
    text = inner
    for _ in range(depth):
        text = template.format(text)
    return text


DEEP_SOURCES = {
    "sin": model(nested("sin({})", 5000)),
    "unary_minus": model("-" * 5000 + "1"),
    "spaced_unary_minus": model("- " * 5000 + "1"),
    "power_tower": model(nested("x ^ ({})", 5000, "2")),
    "if_expression": model(nested("if x > 0 then ({}) else 0", 5000)),
    "ternary": model(nested("x > 0 ? ({}) : 0", 5000)),
    "metadata": "component Deep\n  variable x::Real\nmetadata " + nested('{{"a": {}}}', 5000, "1")
                + "\nend\n",
    "metadata_arrays": "component Deep\n  variable x::Real\nmetadata {\"a\": "
                       + nested("[{}]", 5000, "1") + "}\nend\n",
    "if_blocks": "component Deep\n  variable x::Real\nrelations\n"
                 + "if true\n" * 3000 + "x = 1\n" + "end\n" * 3000 + "end\n",
}


@pytest.mark.parametrize("name", sorted(DEEP_SOURCES))
def test_deep_nesting_is_a_located_error(name):
    with pytest.raises(DyadError) as caught:
        parse_source(DEEP_SOURCES[name], "deep.dyad")
    err = caught.value
    assert err.message == f"nested too deeply: more than {MAX_NESTING} levels of nesting"
    assert err.span is not None and err.span.file == "deep.dyad" and err.span.line >= 2
    assert err.format().startswith(f"deep.dyad:{err.span.line}:{err.span.column}: error: ")


def test_nesting_below_the_limit_parses():
    expr = parse_expression(nested("sin({})", MAX_NESTING // 2 - 2))
    depth = 0
    while isinstance(expr, ast.Call):
        expr, depth = expr.args[0], depth + 1
    assert depth == MAX_NESTING // 2 - 2
    assert parse_expression("-" * (MAX_NESTING - 2) + "1") is not None


def test_cli_reports_deep_nesting_without_a_traceback(tmp_path):
    path = tmp_path / "deep.dyad"
    path.write_text(DEEP_SOURCES["sin"], encoding="utf-8")
    result = subprocess.run([sys.executable, "-m", "compiler", "parse", str(path)], cwd=REPO,
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 1
    assert result.stderr.startswith(f"{path}:4:")
    assert "nested too deeply" in result.stderr
    assert "Traceback" not in result.stderr and "internal" not in result.stderr


def test_parentheses_alone_do_not_nest():
    assert parse_expression("(" * 5000 + "42" + ")" * 5000) == ast.Number(42)


def test_twenty_thousand_term_sum_parses_prints_and_compares():
    terms = " + ".join(f"{i % 9} * x" for i in range(20000)) + " - 1"
    file = parse_source(model(terms), "sum.dyad")
    rhs = file.definitions[0].relations[0].rhs
    first, links = ast.left_chain(rhs, {"+", "-"})
    assert len(links) == 20000 and first == ast.BinaryOp("*", ast.Number(0), ast.Ref((ast.RefPart("x"),)))
    again = parse_source(format_file(file), "sum.dyad<fmt>")
    assert again == file and hash(again) == hash(file)
    assert repr(rhs).startswith("BinaryOp(op='-', left=BinaryOp(op='+'")


@pytest.mark.parametrize("op", ["and", "or", "*", "/", ".+", "&&"])
def test_long_chains_of_other_operators(op):
    expr = parse_expression(f" {op} ".join(["a"] * 5000))
    first, links = ast.left_chain(expr, {op if op != "&&" else "and"})
    assert len(links) == 4999 and first == ast.Ref((ast.RefPart("a"),))


def test_long_integer_literal_is_a_located_error():
    with pytest.raises(DyadError) as caught:
        parse_source(model("7" * 5000), "big.dyad")
    err = caught.value
    assert (err.span.line, err.span.column) == (4, 7)
    assert "5000 digits is too large" in err.message


def test_integers_that_fit_a_float_stay_exact():
    big = "1" + "0" * 307
    assert parse_expression(big).value == 10 ** 307
    assert parse_expression("0" * 400 + "5").value == 5      # leading zeros do not count


@pytest.mark.parametrize("text", ["1e400", "2.5e309", "1" * 400 + ".0", "1000000T" + "0" * 0])
def test_float_literals_that_overflow_are_located_errors(text):
    if text == "1000000T":
        assert parse_expression(text).value == 1e18          # large but finite
        return
    with pytest.raises(DyadError) as caught:
        parse_source(model(text), "big.dyad")
    assert "overflows a 64-bit float" in caught.value.message
    assert (caught.value.span.line, caught.value.span.column) == (4, 7)
