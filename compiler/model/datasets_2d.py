"""DyadData's `DyadInterpolationTable2D`: a grid of values over two axes, read from a CSV file,

    DyadData.DyadInterpolationTable2D("dyad://Pkg/table.csv", axis1_name = "velocity",
                                      axis2_name = "temperature", data_name = "force")

and read back by name: `table["velocity"]` and `table["temperature"]` are the axes (vectors),
`table["force"]` the values (a matrix, one row per point of axis 1), the arguments
`Tables.InterpolatedTable` takes. Dyad's documentation names the three parts but not the file's
layout, so dyadc reads the two layouts a table is written in:

- long: a header row with columns named as the three parts (any order, other columns ignored),
  one row per grid point; each axis is the sorted set of its column's values, and every pair of
  axis values has exactly one row;
- matrix: the first row holds a label, then the points of axis 2; each further row a point of
  axis 1, then its values.

The file is found, bounded and located as a DyadDataset's (compiler/model/datasets.py).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import sympy

from compiler.errors import DyadError, Note, Span, register_source
from compiler.model import datasets
from compiler.model.size_limits import check_elements


@dataclass(frozen=True)
class GridDataset:
    label: str
    names: tuple[str, str, str]                  # axis 1, axis 2, data
    axis1: tuple[float, ...]
    axis2: tuple[float, ...]
    data: tuple[tuple[float, ...], ...]          # data[i][j] at axis1[i], axis2[j]
    span: Span | None

    def part(self, name: str, span: Span | None) -> np.ndarray:
        """The axis or the data named `name`, as a structural array value."""
        if name not in self.names:
            raise DyadError(f"the table has no part `{name}`; it has "
                            f"{', '.join(f'`{n}`' for n in self.names)}", span,
                            notes=[Note("the table is declared here", self.span)])
        value = {self.names[0]: self.axis1, self.names[1]: self.axis2,
                 self.names[2]: self.data}[name]
        return np.vectorize(sympy.Float, otypes=[object])(np.array(value, dtype=float))


def from_csv(path: Path, names: tuple[str, str, str], span: Span | None) -> GridDataset:
    text = _read(path, span)
    file = str(path)
    rows = [(number + 1, [field.strip() for field in line.split(_delimiter(line))])
            for number, line in enumerate(text.splitlines()) if line.strip()]
    if len(rows) < 2:
        raise DyadError(f"data file {path} needs a header row and at least one row of values",
                        span)
    check_elements(sum(len(fields) for _, fields in rows), span, f"the data file {path}")
    header = [field.strip('"') for field in rows[0][1]]
    if all(name in header for name in names):
        return _long(file, header, rows[1:], names, span)
    return _matrix(file, rows, names, span)


def _long(file: str, header: list[str], rows: list, names: tuple[str, str, str],
          span: Span | None) -> GridDataset:
    where = [header.index(name) for name in names]
    points: dict[tuple[float, float], float] = {}
    for line, fields in rows:
        a1, a2, value = (_number(fields, k, file, line, span) for k in where)
        if (a1, a2) in points:
            raise DyadError(f"a second row for {names[0]} = {a1:g}, {names[1]} = {a2:g}",
                            Span(file, line, 1, line, 1), notes=_used_at(span))
        points[a1, a2] = value
    axis1 = sorted({a1 for a1, _ in points})
    axis2 = sorted({a2 for _, a2 in points})
    missing = next(((a1, a2) for a1 in axis1 for a2 in axis2 if (a1, a2) not in points), None)
    if missing is not None:
        raise DyadError(f"data file {file} has no row for {names[0]} = {missing[0]:g}, "
                        f"{names[1]} = {missing[1]:g}: a table needs a value at every pair of "
                        f"axis points", span)
    data = tuple(tuple(points[a1, a2] for a2 in axis2) for a1 in axis1)
    return GridDataset(file, names, tuple(axis1), tuple(axis2), data, span)


def _matrix(file: str, rows: list, names: tuple[str, str, str], span: Span | None) -> GridDataset:
    first_line, header = rows[0]
    if len(header) < 2 or not all(_is_number(field) for field in header[1:]):
        raise DyadError(f"data file {file} has neither columns named "
                        f"{', '.join(f'`{n}`' for n in names)} (one row per grid point) nor a "
                        f"first row of `{names[1]}` values after a label (a matrix)",
                        Span(file, first_line, 1, first_line, 1), notes=_used_at(span))
    axis2 = tuple(_number(header, k, file, first_line, span) for k in range(1, len(header)))
    axis1, data = [], []
    for line, fields in rows[1:]:
        if len(fields) != len(header):
            raise DyadError(f"row has {len(fields)} fields, the first row {len(header)}",
                            Span(file, line, 1, line, 1), notes=_used_at(span))
        axis1.append(_number(fields, 0, file, line, span))
        data.append(tuple(_number(fields, k, file, line, span) for k in range(1, len(fields))))
    return GridDataset(file, names, tuple(axis1), axis2, tuple(data), span)


def _read(path: Path, span: Span | None) -> str:
    try:
        if path.stat().st_size > datasets.MAX_DATA_FILE_BYTES:
            raise DyadError(f"data file {path} is larger than the limit of "
                            f"{datasets.MAX_DATA_FILE_BYTES:,} bytes for data read at compile "
                            f"time", span)
        text = path.read_bytes().decode("utf-8-sig")
    except OSError as exc:
        raise DyadError(f"cannot read data file {path}: {exc.strerror or exc}", span) from None
    except UnicodeDecodeError as exc:
        raise DyadError(f"data file {path} is not UTF-8 text (byte {exc.start + 1})", span) from None
    register_source(str(path), text)
    return text


def _delimiter(line: str) -> str:
    return next((candidate for candidate in (",", "\t", ";") if candidate in line), ",")


def _is_number(text: str) -> bool:
    try:
        return math.isfinite(float(text))
    except ValueError:
        return False


def _number(fields: list[str], position: int, file: str, line: int, span: Span | None) -> float:
    if position >= len(fields) or not _is_number(fields[position]):
        what = "missing" if position >= len(fields) else f"`{fields[position]}`, not a finite number"
        raise DyadError(f"field {position + 1} is {what}", Span(file, line, 1, line, 1),
                        notes=_used_at(span))
    return float(fields[position])


def _used_at(span: Span | None) -> list[Note]:
    return [Note("the table is declared here", span)] if span else []
