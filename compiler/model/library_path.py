"""The library search path: which folders hold Dyad packages, in which order, and which of them
may run Python code.

Order (the first folder that defines a qualified name wins):
  1. the library shipped with dyadc (package `compiler.components`, found with importlib.resources,
     so it works the same from a wheel, an editable install or a source checkout that was installed);
  2. each `-L DIR` (`lib_dirs`), in the order given;
  3. each folder of the environment variable DYADC_PATH (os.pathsep-separated, like MODELICAPATH).
The shipped library comes first so that a user folder cannot silently replace `Dyad.Real` or a
shipped component; a user library adds its own top-level package names instead.

Every folder on this path was named by the user (or ships with dyadc), so its `dyad_functions.py`
plugins may be executed. The folder of a model file given by path is NOT on this path: the library
adds it as a source-only root (its .dyad files resolve, its Python never runs; docs/security.md).
"""
from __future__ import annotations

import importlib.resources
import os
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Sequence

from compiler.errors import DyadError

SHIPPED_LIBRARY_PACKAGE = "compiler.components"
LIBRARY_PATH_VARIABLE = "DYADC_PATH"


@dataclass(frozen=True)
class Root:
    """One folder of the search path and why it is there."""
    path: Path                  # resolved
    origin: str                 # "shipped library", "-L", "DYADC_PATH" or "model folder"
    runs_code: bool             # whether its dyad_functions.py plugins may be executed


@lru_cache(maxsize=None)
def shipped_library_root() -> Path:
    """The folder of the shipped Dyad library inside the installed package."""
    try:
        folder = importlib.resources.files(SHIPPED_LIBRARY_PACKAGE)
    except ModuleNotFoundError:
        raise DyadError(f"the Dyad library shipped with dyadc (package {SHIPPED_LIBRARY_PACKAGE}) "
                        f"is not installed",
                        hint="install dyadc with `pip install .` or `make install` in its source "
                             "folder; running the sources without installing them cannot find "
                             "the library") from None
    path = Path(os.fspath(folder))
    if not path.is_dir():
        raise DyadError(f"the Dyad library shipped with dyadc is not a folder: {path}",
                        hint="reinstall dyadc")
    return path.resolve()


def environment_dirs() -> list[str]:
    """The folders named by DYADC_PATH; empty entries are skipped."""
    return [d for d in os.environ.get(LIBRARY_PATH_VARIABLE, "").split(os.pathsep) if d]


def search_path(lib_dirs: Sequence[str | os.PathLike] = (), *, include_shipped: bool = True,
                use_env: bool = True) -> list[Root]:
    """The roots in lookup order, each folder once (its first position wins). A `-L` folder that
    does not exist is an error (a typo would otherwise only show up as an unknown name); a
    DYADC_PATH entry that does not exist is skipped, as PATH entries are."""
    roots: list[Root] = []
    if include_shipped:
        roots.append(Root(shipped_library_root(), "shipped library", True))
    for folder in lib_dirs:
        path = Path(folder)
        if not path.is_dir():
            raise DyadError(f"library folder `{folder}` (given with -L) is not a directory",
                            hint="-L DIR names a folder whose subfolders are Dyad packages")
        roots.append(Root(path.resolve(), "-L", True))
    if use_env:
        roots.extend(Root(Path(d).resolve(), LIBRARY_PATH_VARIABLE, True)
                     for d in environment_dirs() if Path(d).is_dir())
    unique: list[Root] = []
    for root in roots:
        if all(root.path != seen.path for seen in unique):
            unique.append(root)
    return unique


def describe(roots: Sequence[Root]) -> str:
    """`path (origin), ...` for error messages."""
    return ", ".join(f"{root.path} ({root.origin})" for root in roots)

