"""Dyad's `DyadDataset`: named columns of numbers, one of them the independent variable (time).

    DyadDataset("data/samples.csv", independent_var = "ts", dependent_vars = ["data"])
    DyadDataset(hcat(0:0.1:1, square(0:0.1:1)), independent_var = "ts", dependent_vars = ["data"])
    DyadDataset("owner", "name", independent_var = ..., dependent_vars = [...])     # JuliaHub

A CSV file has a header row that names its columns (any order; the dataset selects its columns by
name). A matrix names its columns in order: the independent variable, then the dependent ones.
A JuliaHub dataset lives on JuliaHub's servers: dyadc does not download data, so it is refused
with its name and what to write instead.

Where a relative file name is looked for: Dyad reads it relative to the directory the Julia
process runs in (a package's tests run in its `test/` folder). A compiled model must not depend on
the directory dyadc runs in, so dyadc looks beside the package instead, in this order: the package
root (the folder holding its `dyad/` folder), the package's `test/` folder, the folder of the
`.dyad` file. `dyad://Pkg/path` is `path` in the `assets/` folder of package `Pkg` on the library
path (where Dyad's "Working with Data" puts it), else under the package's root.

Reading is bounded (issue 19): a file larger than MAX_DATA_FILE_BYTES is refused before it is
read, and the numbers it holds count against the element limit (compiler/model/size_limits.py).
Every problem in a file is a located error at its line and column in that file.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from compiler.errors import DyadError, Note, Span, register_source, suggest_name
from compiler.model.size_limits import check_elements

MAX_DATA_FILE_BYTES = 64 * 1024 * 1024
DYAD_URI = "dyad://"


@dataclass(frozen=True)
class Dataset:
    label: str                                   # where the data came from, for messages
    independent_var: str
    dependent_vars: tuple[str, ...]
    columns: tuple[tuple[str, tuple[float, ...]], ...]   # the selected columns, by name
    span: Span | None                            # the DyadDataset(...) call

    def column(self, name: str) -> tuple[float, ...]:
        return dict(self.columns)[name]


# ------------------------------------------------------------------------------- from a matrix

def from_matrix(matrix: Any, independent_var: str, dependent_vars: tuple[str, ...],
                span: Span | None) -> Dataset:
    """`matrix`: a 2-D array of numbers known at compile time, one column per name."""
    import numpy as np
    names = (independent_var,) + dependent_vars
    if not isinstance(matrix, np.ndarray) or matrix.ndim != 2:
        shape = getattr(matrix, "shape", ())
        raise DyadError(f"a DyadDataset of values needs a matrix (one column per variable), got "
                        f"{'a scalar' if not shape else f'an array of shape {tuple(shape)}'}", span,
                        hint="build it from columns: `hcat(times, values)`")
    if matrix.shape[1] != len(names):
        raise DyadError(f"the DyadDataset's matrix has {matrix.shape[1]} columns but names "
                        f"{len(names)} ({', '.join(names)}): the independent variable first, then "
                        f"each dependent one", span)
    columns = []
    for k, name in enumerate(names):
        values = []
        for row, entry in enumerate(matrix[:, k]):
            try:
                number = float(entry)
            except (TypeError, ValueError):
                raise DyadError(f"row {row + 1} of column `{name}` of the DyadDataset is not a "
                                f"number known at compile time ({entry})", span) from None
            if not math.isfinite(number):
                raise DyadError(f"row {row + 1} of column `{name}` of the DyadDataset is "
                                f"{number}", span)
            values.append(number)
        columns.append((name, tuple(values)))
    return Dataset(f"the table at {span}" if span else "a table", independent_var, dependent_vars,
                   tuple(columns), span)


# ---------------------------------------------------------------------------------- from a file

def locate(name: str, span: Span | None, library_roots: list[Path]) -> Path:
    """The data file `name` (absolute, relative, or dyad://Pkg/path) for a DyadDataset written at
    `span`; a located error that lists every place looked at when it is nowhere."""
    if name.startswith(DYAD_URI):
        package, _, rest = name[len(DYAD_URI):].partition("/")
        folder = next((Path(root) / package for root in library_roots
                       if package and (Path(root) / package).is_dir()), None)
        if folder is None or not rest:
            raise DyadError(f"cannot resolve `{name}`: no package `{package}` on the library path"
                            if folder is None else f"`{name}` names no file inside the package",
                            span, hint="write dyad://Package/path/inside/the/package")
        root = project_root(folder)
        candidates = [root / "assets" / rest, root / rest]       # Dyad's documented place first
    elif Path(name).is_absolute():
        candidates = [Path(name)]
    else:
        source = Path(span.file).resolve().parent if span and not span.file.startswith("<") else None
        candidates = []
        if source is not None:
            root = project_root(source)
            candidates = [root / name, root / "test" / name, source / name]
        candidates = list(dict.fromkeys(candidates))
    for candidate in candidates:
        if candidate.is_file():
            return candidate
    looked = "; ".join(str(c) for c in candidates) or "nowhere (the model was not read from a file)"
    raise DyadError(f"data file `{name}` not found; looked in: {looked}", span,
                    hint="relative names are read from the package root, its test/ folder, then "
                         "the folder of the .dyad file (never the current directory)")


def project_root(folder: Path) -> Path:
    """The folder holding the `dyad/` folder that `folder` is in (itself when in none)."""
    folder = folder.resolve()
    for candidate in (folder, *folder.parents):
        if candidate.name == "dyad":
            return candidate.parent
    return folder


def candidates_read(name: str, span: Span | None) -> list[Path]:
    """Every path `locate` may look at for a relative name: what a cached compile depends on."""
    if name.startswith(DYAD_URI) or Path(name).is_absolute() or span is None \
            or span.file.startswith("<"):
        return []
    source = Path(span.file).resolve().parent
    root = project_root(source)
    return list(dict.fromkeys([root / name, root / "test" / name, source / name]))


def from_csv(path: Path, independent_var: str, dependent_vars: tuple[str, ...],
             span: Span | None) -> Dataset:
    """The selected columns of a CSV file whose first line names its columns."""
    try:
        size = path.stat().st_size
        if size <= MAX_DATA_FILE_BYTES:
            with open(path, "rb") as handle:
                raw = handle.read(MAX_DATA_FILE_BYTES + 1)      # the file may grow meanwhile
            size = len(raw)
    except OSError as exc:
        raise DyadError(f"cannot read data file {path}: {exc.strerror or exc}", span) from None
    if size > MAX_DATA_FILE_BYTES:
        raise DyadError(f"data file {path} is {size:,} bytes or more, above the limit of "
                        f"{MAX_DATA_FILE_BYTES:,} for data read at compile time", span,
                        hint="interpolating that many samples would make every evaluation of the "
                             "model slow; resample the data to fewer rows")
    file = str(path)
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw[:exc.start].count(b"\n") + 1
        raise DyadError(f"data file {path} is not UTF-8 text (byte {exc.start + 1})",
                        Span(file, line, 1, line, 1), notes=_used_at(span)) from None
    register_source(file, text)              # error lines are shown from this text, read once
    lines = text.splitlines()
    header_index = next((i for i, line in enumerate(lines) if line.strip()), None)
    if header_index is None:
        raise DyadError(f"data file {path} is empty", span)
    delimiter = _delimiter(lines[header_index])
    header = _fields(lines[header_index], delimiter)
    names = [name for name, _ in header]
    wanted = (independent_var,) + dependent_vars
    positions = {}
    for name in wanted:
        if name not in names:
            raise DyadError(f"data file {path} has no column `{name}`; its columns are "
                            f"{', '.join(f'`{n}`' for n in names)}",
                            Span(file, header_index + 1, 1, header_index + 1, 1),
                            hint=_hint(name, names), notes=_used_at(span))
        positions[name] = names.index(name)
    values: dict[str, list[float]] = {name: [] for name in wanted}
    for index in range(header_index + 1, len(lines)):
        if not lines[index].strip():
            continue
        check_elements((len(values[independent_var]) + 1) * len(wanted), span,
                       f"the data file {path}")
        fields = _fields(lines[index], delimiter)
        for name in wanted:
            values[name].append(_number(fields, positions[name], name, file, index + 1,
                                        len(lines[index]), span))
    if not values[independent_var]:
        raise DyadError(f"data file {path} has a header but no rows", span)
    return Dataset(str(path), independent_var, dependent_vars,
                   tuple((name, tuple(values[name])) for name in wanted), span)


def _number(fields, position: int, name: str, file: str, line: int, width: int,
            span: Span | None) -> float:
    if position >= len(fields):
        raise DyadError(f"row has {len(fields)} fields, so no value for column `{name}` (field "
                        f"{position + 1})", Span(file, line, width + 1, line, width + 1),
                        notes=_used_at(span))
    text, column = fields[position]
    try:
        number = float(text.strip())
    except ValueError:
        number = None
    if number is None or not math.isfinite(number):
        what = "is empty" if not text.strip() else f"`{text.strip()}` is not a finite number"
        raise DyadError(f"the value of column `{name}` {what}", Span(file, line, column, line,
                                                                   column + max(len(text), 1) - 1),
                        notes=_used_at(span))
    return number


def _delimiter(header: str) -> str:
    for candidate in (",", "\t", ";"):
        if candidate in header:
            return candidate
    return ","


def _fields(line: str, delimiter: str) -> list[tuple[str, int]]:
    """(text, 1-based column) of each field; a field may be quoted with double quotes."""
    out, start, quoted, current = [], 0, False, []
    for position, char in enumerate(line):
        if char == '"':
            quoted = not quoted
        elif char == delimiter and not quoted:
            out.append(("".join(current), start + 1))
            current, start = [], position + 1
            continue
        else:
            current.append(char)
    out.append(("".join(current), start + 1))
    return [(text.strip() if text.strip() else text, column) for text, column in out]


def _used_at(span: Span | None) -> list[Note]:
    return [Note("the dataset is declared here", span)] if span else []


def _hint(name: str, names: list[str]) -> str | None:
    return suggest_name(name, names)


def remote(owner: str, name: str, span: Span | None) -> DyadError:
    return DyadError(f"`DyadDataset(\"{owner}\", \"{name}\", ...)` is the JuliaHub dataset "
                     f"{owner}/{name}: dyadc does not download data", span,
                     hint=f"download it once (JuliaHub.download_dataset((\"{owner}\", \"{name}\"), "
                          f"\"file.csv\")) and name the local file: DyadDataset(\"file.csv\", "
                          f"independent_var = ..., dependent_vars = [...])")
