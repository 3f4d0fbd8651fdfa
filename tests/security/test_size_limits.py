"""Sizes are estimated before anything is allocated (issue 19, item 5): an array, a range, an
unrolled loop, a comprehension or a component array beyond the limit is a located error that
gives the estimate and the limit; the limit is --max-elements N, else $DYADC_MAX_ELEMENTS, else
1,000,000 (docs/security.md). Exact constant powers are folded only while small."""
from __future__ import annotations

import re
import textwrap

import pytest

from compiler.cli import main
from compiler.model.size_limits import DEFAULT_MAX_ELEMENTS, MAX_ELEMENTS_ENV


def write(folder, text: str, name: str = "Big") -> str:
    path = folder / f"{name}.dyad"
    path.write_text(textwrap.dedent(text).lstrip(), encoding="utf-8")
    return str(path)


def check(capsys, path: str, *options) -> tuple[int, str]:
    code = main(["check", path, *options])
    return code, capsys.readouterr().err


def assert_located(err: str, path: str, line: int, column: int, words: str) -> None:
    first = err.splitlines()[0]
    assert first.startswith(f"{path}:{line}:{column}: error: "), err
    assert words in first, err


ARRAY = """
    component Big
      parameter n::Integer = {n}
      variable x::Real[n]
    relations
      for i in 1:n
        x[i] = i
      end
    end
    """


def test_the_default_limit_is_a_million(tmp_path, capsys, monkeypatch):
    monkeypatch.delenv(MAX_ELEMENTS_ENV, raising=False)
    assert DEFAULT_MAX_ELEMENTS == 1_000_000
    path = write(tmp_path, ARRAY.format(n=1_000_001))
    code, err = check(capsys, path)
    assert code == 1
    assert_located(err, path, 3, 3, "the array `x` would create 1,000,001 elements, more than the limit "
                                    "of 1,000,000")
    assert "--max-elements N or $DYADC_MAX_ELEMENTS" in err


def test_the_limit_is_exact_and_set_by_the_option(tmp_path, capsys):
    at_limit = write(tmp_path, ARRAY.format(n=50), "AtLimit")
    assert check(capsys, at_limit, "--max-elements", "50")[0] == 0
    over = write(tmp_path, ARRAY.format(n=51))
    code, err = check(capsys, over, "--max-elements", "50")
    assert code == 1
    assert_located(err, over, 3, 3, "would create 51 elements, more than the limit of 50")


def test_the_limit_from_the_environment_and_the_option_first(tmp_path, capsys, monkeypatch):
    path = write(tmp_path, ARRAY.format(n=20))
    monkeypatch.setenv(MAX_ELEMENTS_ENV, "19")
    code, err = check(capsys, path)
    assert code == 1 and "more than the limit of 19" in err
    assert check(capsys, path, "--max-elements", "20")[0] == 0          # the option wins
    monkeypatch.setenv(MAX_ELEMENTS_ENV, "many")
    code, err = check(capsys, path)
    assert code == 1 and err.startswith("error: $DYADC_MAX_ELEMENTS must be a positive integer, got `many`")
    code, err = check(capsys, path, "--max-elements", "0")
    assert code == 1 and err.startswith("error: --max-elements must be at least 1, got 0")


def test_a_range_is_counted_without_building_it(tmp_path, capsys):
    path = write(tmp_path, """
        component Big
          variable x::Real
        relations
          x = sum([i for i in 1:10^300])
        end
        """)
    code, err = check(capsys, path)
    assert code == 1
    assert_located(err, path, 4, 23, "this range would create about 1e+300 elements")


def test_nested_loops_multiply(tmp_path, capsys):
    path = write(tmp_path, """
        component Big
          variable x::Real[30, 30]
        relations
          for i in 1:30, j in 1:30
            x[i, j] = i + j
          end
        end
        """)
    assert check(capsys, path, "--max-elements", "900")[0] == 0
    code, err = check(capsys, path, "--max-elements", "899")
    assert code == 1
    # the array comes first: 900 elements; the loop alone would be refused at its inner iterator
    assert_located(err, path, 2, 3, "the array `x` would create 900 elements, more than the limit of 899")
    loop_only = write(tmp_path, """
        component Loop
          variable y::Real
        relations
          y = 1
          for i in 1:30, j in 1:30
            initial y = 1
          end
        end
        """, "Loop")
    code, err = check(capsys, loop_only, "--max-elements", "899")
    assert code == 1
    assert_located(err, loop_only, 5, 18, "this `for` loop would create 900 elements")


def test_nested_comprehensions_multiply(tmp_path, capsys):
    path = write(tmp_path, """
        component Big
          variable y::Real
        relations
          y = sum([i * j for i in 1:40, j in 1:40])
        end
        """)
    assert check(capsys, path, "--max-elements", "1600")[0] == 0
    code, err = check(capsys, path, "--max-elements", "1599")
    assert code == 1
    assert_located(err, path, 4, 11, "this comprehension would create 1,600 elements")


def test_zeros_and_fill_are_counted(tmp_path, capsys):
    path = write(tmp_path, """
        component Big
          variable y::Real
        relations
          y = sum(fill(1, 1000, 1000, 1000))
        end
        """)
    code, err = check(capsys, path)
    assert code == 1
    assert_located(err, path, 4, 11, "this array would create 1,000,000,000 elements")


def test_a_component_array_is_estimated_from_its_first_element(tmp_path, capsys):
    path = write(tmp_path, """
        component Cell
          parameter k::Real = 1
          variable x::Real
        relations
          der(x) = -k * x
        end
        component Big
          cells = [Cell() for i in 1:1000000]
        end
        """)
    code, err = check(capsys, path)
    assert code == 1
    # one Cell is 3 scalars (itself, k, x): 1,000,000 of them, 3,000,000 elements, refused after one
    assert_located(err, path, 8, 3, "the component array `cells` (1,000,000 x Cell) would create "
                                    "3,000,000 elements, more than the limit of 1,000,000")
    small = write(tmp_path, """
        component Cell
          parameter k::Real = 1
          variable x::Real(initial = 1)
        relations
          der(x) = -k * x
        end
        component Small
          cells = [Cell() for i in 1:10]
        end
        """, "Small")
    assert check(capsys, small, "--max-elements", "30")[0] == 0
    code, err = check(capsys, small, "--max-elements", "29")
    assert code == 1 and "(10 x Cell) would create 30 elements, more than the limit of 29" in err


@pytest.mark.parametrize("value, words", [
    ("9^9^9", "the power 9^387420489 is too large: about 10^369,693,099"),
    ("2^100000", "the power 2^100000 is too large: about 10^30,102"),
    ("(-3)^(10^6)", "the power (-3)^1000000 is too large"),
])
def test_a_constant_power_beyond_a_float_is_a_located_error(tmp_path, capsys, value, words):
    path = write(tmp_path, f"""
        component Big
          parameter k::Real = {value}
          variable x::Real(initial = 1)
        relations
          der(x) = -k * x
        end
        """)
    code, err = check(capsys, path)
    assert code == 1
    assert_located(err, path, 2, 23, words)


@pytest.mark.parametrize("value, expected", [
    ("(1/2)^100000", 0.0),              # too large to keep exact: a float, which underflows to 0
    ("2^1000 / 2^999", 2.0),            # small enough to stay exact
    ("10^400 / 10^399", 10.0),
])
def test_constant_powers_that_fit_a_float_still_evaluate(tmp_path, capsys, value, expected):
    path = write(tmp_path, f"""
        component Big
          parameter k::Real = {value}
          variable x::Real(initial = 1)
        relations
          der(x) = -k * x
        end
        """)
    code = main(["flatten", path])
    out = capsys.readouterr().out
    assert code == 0
    assert re.search(rf"\bk\b.*= {expected:g}\b", out) or re.search(rf"\bk\b.*{expected}", out), out
