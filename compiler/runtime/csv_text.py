"""The rows of a CSV table as text: every number at `%.17g` (17 significant digits, correctly
rounded, so it parses back to the same double), fields joined by `,`, each row ended by `\\n`.

Formatting is a CSV writer's whole cost, so the rows are made by a small C routine (csv_rows.c)
where its library was built (native_build.py: `make install` builds it when a C compiler is
found); without it, Python's `%` formats each distinct column once. Both write the same bytes
(tests/runtime/test_csv_text.py).
"""
from __future__ import annotations

import ctypes
from pathlib import Path

import numpy as np

from .native_build import csv_library_path

FIELD_BYTES = 32          # room for one number and its separator (at most 25 are used)
_loaded: list = []        # [the library's row function, or None], once per process


def load_rows(library: Path):
    """The row function of a built library (an OSError if it does not load)."""
    function = ctypes.CDLL(str(library)).dyadc_csv_rows
    function.restype = ctypes.c_size_t
    function.argtypes = [ctypes.c_void_p, ctypes.c_int64, ctypes.c_int64, ctypes.c_void_p, ctypes.c_int64,
                         ctypes.c_void_p]
    return function


def _native_rows():
    if not _loaded:
        try:
            _loaded.append(load_rows(csv_library_path()))
        except OSError:
            _loaded.append(None)
    return _loaded[0]


def csv_rows(columns: list[np.ndarray], rows_function=None) -> bytes:
    """The rows of `columns` (float64 arrays of one length) as ASCII text; `rows_function`: a
    library's row function (load_rows), default the built one if any, else Python's `%`."""
    rows_function = rows_function or _native_rows()
    if rows_function is None:
        return python_rows(columns)
    distinct, fields = distinct_columns(columns)
    length = len(distinct[0]) if distinct else 0
    if not length:
        return b""
    pointers = np.array([column.ctypes.data for column in distinct], dtype=np.uintp)
    which = np.array(fields, dtype=np.int64)
    buffer = np.empty(len(fields) * length * FIELD_BYTES, dtype=np.uint8)
    used = rows_function(pointers.ctypes.data, len(distinct), length, which.ctypes.data, len(fields),
                         buffer.ctypes.data)
    if used == ctypes.c_size_t(-1).value:
        raise MemoryError("no memory left to format the CSV rows")
    return buffer[:used].tobytes()


def python_rows(columns: list[np.ndarray]) -> bytes:
    """The same text as csv_rows, by Python's `%` alone: each distinct column is formatted once
    (one `%` over a whole column is a single call into C), a negated one by turning the signs."""
    distinct, fields = distinct_columns(columns)
    texts = [_formatted(column) for column in distinct]
    negated = {f: [t[1:] if t[0] == "-" else "-" + t for t in texts[~f]] for f in fields if f < 0}
    table = [texts[f] if f >= 0 else negated[f] for f in fields]
    return "".join(",".join(row) + "\n" for row in zip(*table)).encode("ascii")


def distinct_columns(columns: list[np.ndarray]) -> tuple[list[np.ndarray], list[int]]:
    """(distinct, fields): the columns that differ (bit for bit), and for each column the index
    of its distinct column, or `~index` where it is that column negated (never for a column with
    NaN, whose `%.17g` has no sign). A model's aliases and opposite flows repeat: the excavator's
    631 signals are 286 distinct columns, 45 of them the negation of another. A ValueError if
    the columns differ in length (the C routine reads each one `length` values far)."""
    index: dict[bytes, int] = {}
    distinct: list[np.ndarray] = []
    fields: list[int] = []
    for column in columns:
        column = np.ascontiguousarray(column, dtype=float).reshape(-1)
        length = len(distinct[0]) if distinct else len(column)
        if len(column) != length:
            raise ValueError(f"a CSV column has {len(column)} values, the first {length}")
        key = column.tobytes()
        found = index.get(key)
        if found is None:
            opposite = index.get((-column).tobytes())
            if opposite is not None and not np.isnan(column).any():
                fields.append(~opposite)
                continue
            found = index[key] = len(distinct)
            distinct.append(column)
        fields.append(found)
    return distinct, fields


def _formatted(column: np.ndarray) -> list[str]:
    """`%.17g` of every number of `column`, the same text as formatting each alone."""
    n = len(column)
    bits = column.view(np.int64)                    # -0.0 prints unlike 0.0: compare bits
    if n and (bits == bits[0]).all():
        return ["%.17g" % column[0]] * n
    return (("%.17g\n" * n) % tuple(column.tolist())).split("\n")[:n]
