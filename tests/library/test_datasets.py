"""DyadDataset values (compiler/model/datasets.py): where a data file is looked for, what a cached
compile depends on, bounded reading, and every bad input as a located error."""
from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from compiler.api import simulate
from compiler.errors import DyadError
from compiler.model import datasets
from compiler.model.flatten import flatten_model
from compiler.model.size_limits import element_limit

HEADER = """
type Interpolant = func(::Real)::Real
type Table = Native

component Lookup
  u = RealInput()
  y = RealOutput()
  structural parameter table::Table
  structural parameter method::Real
  final parameter lookup::Interpolant = dataset_interpolation(method, table)
relations
  y = lookup(u)
end
"""


def model(tmp_path: Path, dataset: str, method: str = "LinearInterpolation",
          csv: str | None = None, csv_at: str = "data/d.csv") -> tuple[str, Path]:
    """A project Proj (dyad/M.dyad, optionally a CSV file at `csv_at` under the project root);
    returns the model spec and the project root."""
    root = tmp_path / "Proj"
    (root / "dyad").mkdir(parents=True)
    source = HEADER + textwrap.dedent(f"""
    component M
      look = Lookup(method = {method}, table = {dataset})
      variable y::Real
    relations
      look.u = time
      y = look.y
    end
    """)
    (root / "dyad" / "M.dyad").write_text(source, encoding="utf-8")
    if csv is not None:
        target = root / csv_at
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(csv, encoding="utf-8")
    return f"{root / 'dyad' / 'M.dyad'}:M", root


def located(spec: str) -> DyadError:
    with pytest.raises(DyadError) as info:
        flatten_model(spec, [])
    return info.value


def look_line(spec: str) -> int:
    """The line of M.dyad that declares the lookup (and its dataset)."""
    lines = Path(spec.rpartition(":")[0]).read_text(encoding="utf-8").splitlines()
    return next(k for k, line in enumerate(lines, 1) if "look = Lookup" in line)


def file_dataset(name: str = "data/d.csv", columns: str = '["v"]') -> str:
    return f'DyadDataset("{name}", independent_var = "t", dependent_vars = {columns})'


def test_relative_names_are_read_beside_the_package_in_a_fixed_order(tmp_path, monkeypatch):
    spec, root = model(tmp_path, file_dataset(), csv="t,v\n0,1\n1,3\n", csv_at="test/data/d.csv")
    monkeypatch.chdir(tmp_path)                     # the current directory plays no part
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "d.csv").write_text("t,v\n0,100\n1,100\n", encoding="utf-8")
    assert simulate(spec, stop=1.0, points=3)["y"][1] == pytest.approx(2.0)
    (root / "data").mkdir()                          # the package root comes before test/
    (root / "data" / "d.csv").write_text("t,v\n0,10\n1,30\n", encoding="utf-8")
    assert simulate(spec, stop=1.0, points=3)["y"][1] == pytest.approx(20.0)


def test_a_cached_compile_sees_the_data_file_change(tmp_path):
    spec, root = model(tmp_path, file_dataset(), csv="t,v\n0,1\n1,3\n")
    assert simulate(spec, stop=1.0, points=3, cache=True)["y"][2] == pytest.approx(3.0)
    (root / "data" / "d.csv").write_text("t,v\n0,1\n1,5\n", encoding="utf-8")
    assert simulate(spec, stop=1.0, points=3, cache=True)["y"][2] == pytest.approx(5.0)


def test_a_missing_file_names_every_place_looked(tmp_path):
    spec, root = model(tmp_path, file_dataset("data/none.csv"))
    error = located(spec)
    assert "data file `data/none.csv` not found" in error.message
    for place in (root / "data" / "none.csv", root / "test" / "data" / "none.csv",
                  root / "dyad" / "data" / "none.csv"):
        assert str(place.resolve()) in error.message
    assert Path(error.span.file).name == "M.dyad" and error.span.line == look_line(spec)


def test_a_missing_column_is_located_at_the_header(tmp_path):
    spec, root = model(tmp_path, file_dataset(columns='["value"]'), csv="t,v\n0,1\n1,3\n")
    error = located(spec)
    assert "has no column `value`" in error.message and "`t`, `v`" in error.message
    assert error.span.file.endswith("d.csv") and error.span.line == 1
    assert Path(error.notes[0].span.file).name == "M.dyad"


@pytest.mark.parametrize("rows, message, line, column", [
    ("0,1\n0.5,x\n", "`x` is not a finite number", 3, 5),
    ("0,1\n0.5,\n", "is empty", 3, 5),
    ("0,1\n1,NaN\n", "`NaN` is not a finite number", 3, 3),
    ("0,1\n0.5\n", "no value for column `v`", 3, 4),
])
def test_bad_numbers_are_located_in_the_file(tmp_path, rows, message, line, column):
    spec, _ = model(tmp_path, file_dataset(), csv="t,v\n" + rows)
    error = located(spec)
    assert message in error.message
    assert error.span.file.endswith("d.csv") and (error.span.line, error.span.column) == (line, column)
    assert "d.csv:" in error.format()                       # FILE:LINE:COL with the line shown


def test_times_that_do_not_increase_are_refused_at_the_interpolation(tmp_path):
    spec, _ = model(tmp_path, file_dataset(), csv="t,v\n0,1\n1,2\n1,3\n")
    error = located(spec)
    assert "strictly increasing" in error.message and "sample 3" in error.message


def test_a_large_file_is_refused_before_it_is_read(tmp_path, monkeypatch):
    spec, _ = model(tmp_path, file_dataset(), csv="t,v\n" + "".join(f"{k},{k}\n" for k in range(50)))
    monkeypatch.setattr(datasets, "MAX_DATA_FILE_BYTES", 100)
    assert "above the limit of 100" in located(spec).message


def test_an_unreadable_file_is_a_located_error(tmp_path, monkeypatch):
    spec, _ = model(tmp_path, file_dataset(), csv="t,v\n0,1\n")

    def refuse(*args, **kwargs):
        raise PermissionError(13, "Permission denied")
    monkeypatch.setattr(datasets, "open", refuse, raising=False)     # shadows the builtin there
    error = located(spec)
    assert "cannot read data file" in error.message and "Permission denied" in error.message


def test_the_rows_read_count_against_the_element_limit(tmp_path):
    spec, _ = model(tmp_path, file_dataset(), csv="t,v\n" + "".join(f"{k},{k}\n" for k in range(50)))
    with element_limit(40):
        error = located(spec)
    assert "the data file" in error.message and "more than the limit of 40" in error.message


def test_a_juliahub_dataset_is_named_and_not_downloaded(tmp_path):
    spec, _ = model(tmp_path, 'DyadDataset("someone", "circuit", independent_var = "t", '
                              'dependent_vars = ["i"])', method="QuadraticInterpolation")
    error = located(spec)
    assert "JuliaHub dataset someone/circuit" in error.message
    assert "does not download" in error.message and error.span.line == look_line(spec)


@pytest.mark.parametrize("dataset, message", [
    ('DyadDataset(hcat([0, 1], [1, 2], [3, 4]), independent_var = "t", dependent_vars = ["v"])',
     "has 3 columns but names 2"),
    ('DyadDataset(hcat([0, 1], [1, 2], [3, 4]), independent_var = "t", dependent_vars = ["a", "b"])',
     "interpolates one dependent variable"),
    ('DyadDataset([0, 1], independent_var = "t", dependent_vars = ["v"])', "needs a matrix"),
    ('DyadDataset("d.csv", independent_var = "t", dependent_vars = ["v"], delim = ";")',
     "does not support the option `delim`"),
    ('DyadDataset("d.csv", dependent_vars = ["v"])', "needs `independent_var = ...`"),
])
def test_malformed_datasets_are_located_errors(tmp_path, dataset, message):
    spec, _ = model(tmp_path, dataset)
    error = located(spec)
    assert message in error.message and Path(error.span.file).name == "M.dyad"


def test_an_unknown_kind_is_an_error_and_no_dataset_stays_opaque(tmp_path):
    spec, _ = model(tmp_path, file_dataset(), method="SplineOfMyOwn", csv="t,v\n0,1\n1,2\n")
    assert "unknown name `SplineOfMyOwn`" in located(spec).message
    lookup_alone = f"{spec.rpartition(':')[0]}:Lookup"          # checked alone: nothing to build
    flat = flatten_model(lookup_alone, [])
    assert any("lookup" in str(e.residual) for e in flat.equations)
