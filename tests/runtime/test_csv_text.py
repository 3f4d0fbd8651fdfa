"""CSV rows (compiler/runtime/csv_text.py): the C formatter (csv_rows.c, built here into a
temporary folder) writes exactly the text of Python's `"%.17g" % x` for every double, and so does
the Python path, for tables with repeated, negated, constant and NaN columns; the text parses back
to the same doubles."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from compiler.runtime import csv_text
from compiler.runtime.native_build import build_csv_library, csv_library_path, find_compiler

needs_cc = pytest.mark.skipif(find_compiler() is None, reason="no C compiler")

# powers of ten and their neighbours (where the decimal exponent is decided), exact ties at the
# 17th digit (2251799813685247.75 rounds to even: ...478), the ends of the double range, and
# the numbers the fast path hands to snprintf (below 1e-11, above 1e44, subnormal)
EDGES = [0.0, -0.0, math.inf, -math.inf, math.nan, 2251799813685247.75, 2251799813685246.25, 0.5,
         1e-4, 1e-5, 9.9999999999999995e-08, 1e16, 1e17, 123456.0, 9007199254740993.0, 5e-324,
         2.2250738585072014e-308, 1.7976931348623157e308, 3.2e-17, -7.5e-300, 6.02e44, 1e-11]
EDGES += [s * float(v) for k in range(-30, 50) for v in np.nextafter(10.0 ** k, [0.0, 10.0 ** k, math.inf])
          for s in (1, -1)]


def percent_g(values) -> list[str]:
    return ["%.17g" % x for x in values]


@pytest.fixture(scope="module")
def c_rows(tmp_path_factory):
    if find_compiler() is None:
        pytest.skip("no C compiler")
    return csv_text.load_rows(build_csv_library(tmp_path_factory.mktemp("csv-library")))


def lines(text: bytes) -> list[str]:
    return text.decode("ascii").split("\n")[:-1]


@needs_cc
def test_the_c_formatter_writes_percent_17g_at_the_edges(c_rows):
    assert lines(csv_text.csv_rows([np.array(EDGES)], c_rows)) == percent_g(EDGES)


@needs_cc
@settings(max_examples=40, deadline=None)
@given(st.lists(st.integers(0, 2**64 - 1), min_size=1, max_size=400))
def test_the_c_formatter_writes_percent_17g_of_any_bit_pattern(c_rows, patterns):
    values = np.array(patterns, dtype=np.uint64).view(np.float64)
    text = lines(csv_text.csv_rows([values], c_rows))
    assert text == percent_g(values.tolist())
    parsed = np.array([float(t) for t in text])
    assert np.array_equal(parsed, values, equal_nan=True)


@needs_cc
def test_the_c_formatter_writes_percent_17g_across_magnitudes(c_rows):
    rng = np.random.default_rng(28)
    values = rng.standard_normal(50_000) * 10.0 ** rng.integers(-14, 20, 50_000)
    assert lines(csv_text.csv_rows([values], c_rows)) == percent_g(values.tolist())


def table_columns() -> list[np.ndarray]:
    """A table as a model's outputs make them: aliases, opposite flows, constants, a -0 column
    beside a 0 column, NaN in a column and in its negation, a value held over several rows."""
    time = np.linspace(0.0, 1.0, 7)
    x = np.sin(3 * time) * 1e-3
    held = np.array([1.0, 1.0, 1.0, 2.5, 2.5, -0.0, -0.0])
    with_nan = np.array([1.0, np.nan, -2.0, 3.0, 0.0, -0.0, 7.0])
    return [time, x, x.copy(), -x, np.full(7, 2.5), np.zeros(7), -np.zeros(7), held, -held,
            with_nan, -with_nan, np.full(7, -np.inf), np.exp(50 * time)]


def expected_rows(columns) -> list[str]:
    return [",".join(row) for row in zip(*(percent_g(c.tolist()) for c in columns))]


@needs_cc
def test_c_rows_of_a_table_with_repeated_columns_are_each_number_formatted_alone(c_rows):
    columns = table_columns()
    assert lines(csv_text.csv_rows(columns, c_rows)) == expected_rows(columns)


def test_python_rows_of_a_table_with_repeated_columns_are_each_number_formatted_alone():
    columns = table_columns()
    assert lines(csv_text.python_rows(columns)) == expected_rows(columns)


def test_distinct_columns_name_aliases_and_negations_but_never_negate_nan():
    columns = table_columns()
    distinct, fields = csv_text.distinct_columns(columns)
    assert fields[:4] == [0, 1, 1, ~1]          # time, x, its alias, its negation
    assert fields[5:9] == [3, ~3, 4, ~4]        # 0 and -0, a held value and its negation
    assert fields[9:11] == [5, 6]               # a column with NaN and its negation: both kept
    assert len(distinct) == len(columns) - 4


def test_columns_of_different_lengths_are_refused_before_any_formatting():
    with pytest.raises(ValueError, match="a CSV column has 2 values, the first 3"):
        csv_text.csv_rows([np.zeros(3), np.zeros(2)])


def test_the_library_is_named_by_the_source_it_was_built_from(tmp_path, monkeypatch):
    source = tmp_path / "csv_rows.c"
    source.write_text("int a;\n")
    monkeypatch.setattr("compiler.runtime.native_build.CSV_SOURCE", source)
    first = csv_library_path()
    source.write_text("int b;\n")
    assert csv_library_path() != first and csv_library_path().parent == tmp_path


@needs_cc
def test_a_build_removes_the_libraries_of_older_sources(tmp_path):
    (tmp_path / "csv_rows-0123456789abcdef.so").write_bytes(b"built from an older csv_rows.c")
    built = build_csv_library(tmp_path)
    assert sorted(tmp_path.iterdir()) == [built] and built == csv_library_path(tmp_path)
