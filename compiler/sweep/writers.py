"""Write a table of named columns as Parquet (pyarrow) or CSV, chosen by the file's extension,
atomically: the file appears whole or not at all."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Mapping

import numpy as np

from compiler.errors import DyadError
from compiler.runtime.writers import atomic_write

EXTENSIONS = {".parquet": "parquet", ".pq": "parquet", ".csv": "csv"}


def table_format(path: str | os.PathLike) -> str:
    suffix = Path(path).suffix.lower()
    if suffix not in EXTENSIONS:
        raise DyadError(f"cannot tell the format of `{path}` from its extension",
                        hint="name the output FILE.parquet or FILE.csv")
    return EXTENSIONS[suffix]


def sibling(path: str | os.PathLike, tag: str) -> Path:
    """`out/sweep.parquet`, 'partial' -> `out/sweep.partial.parquet`."""
    path = Path(path)
    return path.with_name(f"{path.stem}.{tag}{path.suffix}")


def write_table(columns: Mapping[str, np.ndarray | list], path: str | os.PathLike,
                units: Mapping[str, str] | None = None) -> Path:
    """`units` (column -> unit) go into the Parquet field metadata (`unit`), as `dyadc simulate`'s
    tables carry them; a CSV stays a plain table."""
    path = Path(path)
    if table_format(path) == "parquet":
        try:
            import pyarrow as pa
            import pyarrow.parquet as pq
        except ImportError:
            raise DyadError("writing Parquet needs pyarrow, which is not installed",
                            hint="pip install 'dyadc[sweep]' (make install does), or write FILE.csv") \
                from None
        units = {name: unit for name, unit in (units or {}).items() if unit}
        arrays = [_arrow_column(pa, values) for values in columns.values()]
        fields = [pa.field(name, array.type, metadata={"unit": units[name]} if name in units else None)
                  for name, array in zip(columns, arrays)]
        table = pa.Table.from_arrays(arrays, schema=pa.schema(fields))
        atomic_write(path, lambda tmp: pq.write_table(table, tmp))
    else:
        atomic_write(path, lambda tmp: _write_csv(columns, tmp))
    return path


def _arrow_column(pa, values):
    array = np.asarray(values)
    if array.dtype.kind in "US" or array.dtype == object:
        return pa.array([None if v is None else str(v) for v in values], type=pa.string())
    return pa.array(array)


def _write_csv(columns: Mapping[str, np.ndarray | list], path: str) -> None:
    names = list(columns)
    rows = len(next(iter(columns.values()))) if names else 0
    cells = [[_csv_cell(v) for v in columns[n]] for n in names]
    with open(path, "w", encoding="utf-8", newline="\n") as out:
        out.write(",".join(_quote(n) for n in names) + "\n")
        for i in range(rows):
            out.write(",".join(column[i] for column in cells) + "\n")


def _csv_cell(value) -> str:
    if value is None:
        return ""
    if isinstance(value, (str, np.str_)):
        return _quote(str(value))
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    return "%.17g" % float(value)


def _quote(text: str) -> str:
    if any(c in text for c in ',"\n\r'):
        return '"' + text.replace('"', '""') + '"'
    return text
