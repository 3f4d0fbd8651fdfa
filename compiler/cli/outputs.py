"""Output files of the command line: checked before any work, written all together or not at all.

A bad `--plot` name must not be found after a ten-minute simulation, and must not leave the CSV
of the same run behind: every path is checked first (not a folder, a writable place, a known
extension), and the files are staged beside their targets and moved into place only when every
one of them was written.
"""
from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Callable, Sequence

from compiler.errors import DyadError


def check_simulate_outputs(output: str | None, plot: str | None, events: str | None = None) -> None:
    """`--output`, `--plot` and `--events` of `dyadc simulate`: places that can be written, known
    extensions (disjoint for tables and plots, so the two never name one file), the packages they
    need."""
    if events:
        check_output_file(events, "--events")
        if not events.lower().endswith(".csv"):
            raise DyadError(f"--events `{events}`: events are written as CSV", hint="name it FILE.csv")
        if events in (output, plot):
            raise DyadError(f"--events `{events}` names the same file as --output or --plot")
    from compiler.runtime.plotting import PlotFormatError, plot_format
    from compiler.runtime.writers import OutputFormatError, check_table_writer

    if output:
        check_output_file(output, "--output")
    if plot:
        check_output_file(plot, "--plot")
    try:
        if output:
            check_table_writer(output)
        if plot:
            plot_format(plot)
    except (OutputFormatError, PlotFormatError) as err:
        raise DyadError(str(err)) from None


def write_result(result, names: Sequence[str], units: dict, title: str, output: str | None,
                 plot: str | None, events: str | None = None) -> list[str]:
    """The table (with its sidecar for CSV), the plot and the events of a run: all written or
    none. Returns the paths written."""
    from compiler.runtime.plotting import plot_signals
    from compiler.runtime.writers import sidecar_path, write_events, write_sidecar, write_table

    columns = {name: result[name] for name in names}
    outputs = []
    if output:
        outputs.append((output, lambda path: write_table(path, result.time, columns, units,
                                                         parameters=result.parameters)))
        sidecar = sidecar_path(output)
        if sidecar is not None:
            outputs.append((sidecar, lambda path: write_sidecar(
                path, {n: units.get(n, "") for n in columns}, result.parameters, title)))
    if plot:
        outputs.append((plot, lambda path: plot_signals(path, result.time, columns, units, title)))
    if events:
        outputs.append((events, lambda path: write_events(path, result.events)))
    write_all_or_none(outputs)
    return [target for target, _ in outputs]


def listed(paths: Sequence[str]) -> str:
    """`a`, `a and b`, `a, b and c`: the files a command says it wrote."""
    return ", ".join(paths[:-1]) + f" and {paths[-1]}" if len(paths) > 1 else "".join(paths)


def check_output_file(path: str, option: str) -> None:
    """`path` can be created or replaced as a file: not a folder, under a writable folder."""
    target = Path(path)
    if target.is_dir():
        raise DyadError(f"{option} `{path}` is a folder", hint=f"give a file name, e.g. {path.rstrip('/')}/out"
                                                              f"{target.suffix or '.csv'}")
    if path.endswith(("/", os.sep)):
        raise DyadError(f"{option} `{path}` names a folder, not a file")
    check_writable_folder(str(target.parent), f"{option} `{path}`")


def check_output_folder(path: str, option: str) -> None:
    """`path` is a folder, or can be created as one, in a writable place."""
    target = Path(path)
    if target.exists() and not target.is_dir():
        raise DyadError(f"{option} `{path}` exists and is not a folder")
    check_writable_folder(path, f"{option} `{path}`")


def check_writable_folder(folder: str, what: str) -> None:
    """The folder (or, when it does not exist yet, the nearest existing ancestor in which it would
    be created) is a folder the user may write in."""
    existing = Path(os.path.abspath(folder or "."))
    while not existing.exists():
        if existing.is_symlink():
            raise DyadError(f"{what}: `{existing}` is a dangling symbolic link")
        existing = existing.parent
    if not existing.is_dir():
        raise DyadError(f"{what}: `{existing}` is a file, not a folder")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise DyadError(f"{what}: cannot write in `{existing}` (no permission or a read-only file system)")


def write_all_or_none(outputs: Sequence[tuple[str, Callable[[str], None]]]) -> None:
    """Call each `write(staging_path)`; when all succeeded, move the staged files onto their
    targets. On any failure nothing is left: no staged file, no folder created for them."""
    staged: list[tuple[str, str]] = []
    created: list[Path] = []
    try:
        for target, write in outputs:
            folder = Path(os.path.abspath(target)).parent
            created.extend(_make_folders(folder))
            stem, suffix = os.path.splitext(os.path.basename(target))
            handle, staging = tempfile.mkstemp(prefix=f".{stem}.", suffix=f".staged{suffix}", dir=folder)
            os.close(handle)
            staged.append((staging, target))
            write(staging)
        for staging, target in staged:
            os.replace(staging, target)
    except BaseException:
        for staging, _ in staged:
            if os.path.exists(staging):
                os.unlink(staging)
        for folder in reversed(created):
            try:
                folder.rmdir()
            except OSError:
                pass
        raise


def _make_folders(folder: Path) -> list[Path]:
    """Create `folder` and missing ancestors; return those created, outermost first."""
    missing = []
    while not folder.exists():
        missing.append(folder)
        folder = folder.parent
    for path in reversed(missing):
        path.mkdir()
    return list(reversed(missing))
