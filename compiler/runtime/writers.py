"""Result tables written in the format their file extension names: CSV, Parquet, MATLAB .mat, .npz.

Every write is atomic: the data goes to a temporary file in the target's folder, which then
replaces the target, so a reader (or a crash) never sees half a file. Only numpy and the standard
library are imported here; pyarrow and scipy are imported when their format is asked for.

Layouts (a column is a signal; `time` comes first):
- .csv      header `time,a,b`, one row per time, every number at `%.17g` (csv_text.py); the
            run's parameters and the units go to a sidecar `FILE.csv.json` (`sidecar_path`,
            `write_sidecar`), so that the CSV stays a plain table;
- .parquet  one float64 column per signal; a column's unit is in its field metadata (`unit`), the
            parameters in the schema metadata (`parameters`: a JSON object name -> value);
- .mat      `time` (vector), `names` and `units` (cell arrays of strings), `values` (one row per
            time, one column per name): signal names such as `body.frame_a.x` are not MATLAB
            identifiers, so they travel as strings; likewise `parameter_names` and
            `parameter_values`;
- .npz      one array per signal under its own name, plus `__units__` (pairs of name and unit) and
            `__parameter_names__`, `__parameter_values__`.
Events go to CSV as `time,event,direction` (`write_events`).
"""
from __future__ import annotations

import json
import os
import tempfile
import zipfile
from typing import Callable, Mapping

import numpy as np

from .csv_text import csv_rows

SUPPORTED_EXTENSIONS = (".csv", ".parquet", ".mat", ".npz")
_NPZ_UNITS = "__units__"
_NPZ_PARAMETER_NAMES, _NPZ_PARAMETER_VALUES = "__parameter_names__", "__parameter_values__"
_RESERVED = ("time", _NPZ_UNITS, _NPZ_PARAMETER_NAMES, _NPZ_PARAMETER_VALUES)
_EXTRA = "io"          # pip install 'dyadc[io]' brings pyarrow and scipy


class OutputFormatError(ValueError):
    """An extension no writer handles, or a missing optional package."""


def table_format(path: str | os.PathLike) -> str:
    """The extension of `path` if it names a supported format; an OutputFormatError otherwise."""
    extension = os.path.splitext(os.fspath(path))[1].lower()
    if extension not in SUPPORTED_EXTENSIONS:
        shown = extension or "no extension"
        raise OutputFormatError(f"cannot write a table to `{os.fspath(path)}` ({shown}): supported "
                                f"extensions are {', '.join(SUPPORTED_EXTENSIONS)}")
    return extension


def write_table(path: str | os.PathLike, time, columns: Mapping[str, np.ndarray],
                units: Mapping[str, str] | None = None,
                parameters: Mapping[str, float] | None = None) -> None:
    """Write `time` and `columns` (name -> values on the time grid) to `path` in the format of its
    extension, atomically; `units` (name -> unit string) label the columns and `parameters` (name
    -> value) go into the file's metadata where the format has some (for CSV: write_sidecar)."""
    extension = table_format(path)
    time = np.asarray(time, dtype=float).reshape(-1)
    data = {name: np.asarray(values, dtype=float).reshape(-1) for name, values in columns.items()}
    for name, values in data.items():
        if name in _RESERVED:
            raise ValueError(f"a column may not be called '{name}': the table reserves that name")
        if values.shape != time.shape:
            raise ValueError(f"column '{name}' has {values.size} values but the time grid has {time.size}")
    units = {name: unit for name, unit in (units or {}).items() if unit}
    writer = _WRITERS[extension]
    prepare = _PREPARE.get(extension)
    if prepare is not None:
        prepare()              # a missing package fails before any file is created
    parameters = {name: float(value) for name, value in (parameters or {}).items()}
    atomic_write(path, lambda temp: writer(temp, time, data, units, parameters))


def sidecar_path(path: str | os.PathLike) -> str | None:
    """Where the metadata of a table at `path` goes when the format has no place for it:
    `FILE.csv.json` beside a CSV; None for the other formats."""
    path = os.fspath(path)
    return path + ".json" if table_format(path) == ".csv" else None


def write_sidecar(path: str | os.PathLike, units: Mapping[str, str], parameters: Mapping[str, float],
                  model: str = "") -> None:
    """The sidecar of a CSV table: {"model", "units", "parameters"} as JSON, atomically."""
    content = {"model": model, "units": {n: u for n, u in units.items() if u},
               "parameters": {n: float(v) for n, v in parameters.items()}}
    text = json.dumps(content, indent=1, allow_nan=True) + "\n"
    atomic_write(path, lambda temp: _write_text(temp, text))


def write_events(path: str | os.PathLike, events) -> None:
    """Located events as CSV `time,event,direction`, one row per event, atomically."""
    rows = ["time,event,direction"] + [
        f"{'%.17g' % e['time']},{_csv_field(str(e['event']))},{e.get('direction', '')}" for e in events]
    atomic_write(path, lambda temp: _write_text(temp, "\n".join(rows) + "\n"))


def _write_text(temp: str, text: str) -> None:
    with open(temp, "w", encoding="utf-8", newline="\n") as out:
        out.write(text)


# ------------------------------------------------------------------------------------------ formats

def _write_csv(temp: str, time: np.ndarray, data: dict, units: dict, parameters: dict) -> None:
    header = ",".join(_csv_field(name) for name in ["time", *data])
    body = csv_rows([time, *data.values()])
    with open(temp, "wb") as out:
        out.write(header.encode("utf-8") + b"\n")
        out.write(body)


def _csv_field(name: str) -> str:
    if any(c in name for c in ',"\n'):
        return '"' + name.replace('"', '""') + '"'
    return name


def _write_parquet(temp: str, time: np.ndarray, data: dict, units: dict, parameters: dict) -> None:
    pa, pq = _pyarrow()
    fields, arrays = [pa.field("time", pa.float64(), metadata={"unit": "s"})], [pa.array(time)]
    for name, values in data.items():
        metadata = {"unit": units[name]} if name in units else None
        fields.append(pa.field(name, pa.float64(), metadata=metadata))
        arrays.append(pa.array(values))
    schema = pa.schema(fields, metadata={"parameters": json.dumps(parameters)})
    pq.write_table(pa.Table.from_arrays(arrays, schema=schema), temp)


def _write_mat(temp: str, time: np.ndarray, data: dict, units: dict, parameters: dict) -> None:
    savemat = _savemat()
    names = list(data)
    cells = np.empty(len(names), dtype=object)
    unit_cells = np.empty(len(names), dtype=object)
    for i, name in enumerate(names):
        cells[i] = name
        unit_cells[i] = units.get(name, "")
    values = np.vstack(list(data.values())).T if names else np.zeros((time.size, 0))
    parameter_names = np.empty(len(parameters), dtype=object)
    parameter_names[:] = list(parameters)
    savemat(temp, {"time": time.reshape(-1, 1), "names": cells, "units": unit_cells, "values": values,
                   "parameter_names": parameter_names,
                   "parameter_values": np.array(list(parameters.values()), dtype=float).reshape(-1, 1)},
            do_compression=True, oned_as="column")


def _write_npz(temp: str, time: np.ndarray, data: dict, units: dict, parameters: dict) -> None:
    """As numpy.savez_compressed writes it, but without passing names as keyword arguments (a
    signal called `file` would collide with savez's own parameter)."""
    pairs = np.array([[name, units.get(name, "")] for name in data], dtype=str).reshape(-1, 2)
    arrays = {"time": time, _NPZ_UNITS: pairs,
              _NPZ_PARAMETER_NAMES: np.array(list(parameters), dtype=str),
              _NPZ_PARAMETER_VALUES: np.array(list(parameters.values()), dtype=float), **data}
    with zipfile.ZipFile(temp, "w", compression=zipfile.ZIP_DEFLATED, allowZip64=True) as archive:
        for name, array in arrays.items():
            with archive.open(name + ".npy", "w", force_zip64=True) as member:
                np.lib.format.write_array(member, np.asanyarray(array), allow_pickle=False)


_WRITERS: dict[str, Callable] = {".csv": _write_csv, ".parquet": _write_parquet, ".mat": _write_mat,
                                 ".npz": _write_npz}


def _pyarrow():
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        raise OutputFormatError(f"writing .parquet needs pyarrow: pip install 'dyadc[{_EXTRA}]' "
                                "(or pip install pyarrow)") from None
    return pa, pq


def _savemat():
    try:
        from scipy.io import savemat
    except ImportError:
        raise OutputFormatError(f"writing .mat needs scipy: pip install 'dyadc[{_EXTRA}]' "
                                "(or pip install scipy)") from None
    return savemat


_PREPARE: dict[str, Callable] = {".parquet": _pyarrow, ".mat": _savemat}


def check_table_writer(path: str | os.PathLike) -> None:
    """Everything about writing `path` that can be known before there is data: a supported
    extension and its package installed."""
    prepare = _PREPARE.get(table_format(path))
    if prepare is not None:
        prepare()


# ------------------------------------------------------------------------------------------- atomic

def atomic_write(path: str | os.PathLike, write: Callable[[str], None], mode: int | None = None) -> None:
    """`write(temp)` into a sibling temporary that then replaces `path`; the temporary keeps the
    extension (some writers append theirs otherwise) and is removed on any failure. `mode`: the
    file's permissions (default: what a plain open() gives; the compilation cache asks 0o600)."""
    target = os.path.abspath(os.fspath(path))
    directory, base = os.path.split(target)
    os.makedirs(directory, exist_ok=True)
    stem, extension = os.path.splitext(base)
    handle, temp = tempfile.mkstemp(prefix=f".{stem}.", suffix=f".tmp{extension}", dir=directory)
    os.close(handle)
    try:
        write(temp)
        with open(temp, "rb+") as written:
            os.fsync(written.fileno())
        # mkstemp makes the file private (0600); the output gets the mode a plain open() gives
        os.chmod(temp, 0o666 & ~_umask() if mode is None else mode)
        os.replace(temp, target)
    except BaseException:
        try:
            os.unlink(temp)
        except OSError:
            pass
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
