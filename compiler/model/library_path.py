"""The library search path: which folders hold Dyad packages, in which order, and which of them
may run Python code.

Roots, in the order listed:
  1. the library shipped with dyadc (package `compiler.components`, found with importlib.resources,
     so it works the same from a wheel, an editable install or a source checkout that was installed);
  2. each `-L DIR` (`lib_dirs`), in the order given;
  3. each folder of the environment variable DYADC_PATH (os.pathsep-separated, like MODELICAPATH).

A package is one unit, as in Julia: the top-level folder `P` of exactly one root provides all of
package `P` (`package_provider`). The user's roots (2, 3, then a model file's folder) are asked first, in
their order, then the shipped library: a user's package `P` *replaces* the shipped `P` (a
note names both folders), it never merges with it. The base library `Dyad` is the exception: it is
always the shipped one. A user folder `P` that only adds definitions to the shipped `P` (none of its
names is one of the shipped package's, and it has no Project.toml, nor is it the `dyad/` folder of a
Julia project that has one) is a located error saying how to
name its own package (`check_user_packages`).

Every folder on this path was named by the user (or ships with dyadc), so its `dyad_functions.py`
plugins may be executed. The folder of a model file given by path is NOT on this path: the library
adds it as a source-only root (its .dyad files resolve, its Python never runs; docs/security.md).
"""
from __future__ import annotations

import importlib.resources
import os
import re
import warnings
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Sequence

from compiler.errors import DyadError, Span

SHIPPED_LIBRARY_PACKAGE = "compiler.components"
LIBRARY_PATH_VARIABLE = "DYADC_PATH"
BASE_PACKAGE = "Dyad"
PROJECT_FILE = "Project.toml"
USER_ORIGINS = ("-L", LIBRARY_PATH_VARIABLE, "model folder")
_HEADER = re.compile(r"(?m)^[ \t]*(?:partial\s+)?(?:component|connector|type|enum|analysis|struct)"
                     r"\s+(\w+)")


class PackageNote(UserWarning):
    """`note: package P from FOLDER replaces the shipped one in FOLDER`, printed as written."""
    located = True


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
    check_user_packages(unique)
    return unique


def package_order(roots: Sequence[Root], package: str) -> list[Root]:
    """The roots in the order they are asked for top-level package `package`: the user's (-L,
    DYADC_PATH, a model file's folder, in path order) before the shipped library, whose package a
    user's replaces; the base library `Dyad` from the shipped library first."""
    shipped_rank = -1 if package == BASE_PACKAGE else 1
    return sorted(roots, key=lambda root: shipped_rank if root.origin == "shipped library" else 0)


def package_provider(roots: Sequence[Root], package: str) -> Root | None:
    """The one root whose folder `package` provides all of top-level package `package`."""
    for root in package_order(roots, package):
        try:
            if (root.path / package).is_dir():
                return root
        except OSError:             # a name longer than a file name may be
            return None
    return None


def _definition_names(folder: Path) -> dict[tuple[str, ...], tuple[Path, int, int]]:
    """(subpackage parts..., name) -> (file, line, column) of each definition header below `folder`
    (a text scan, no parse)."""
    found: dict[tuple[str, ...], tuple[Path, int, int]] = {}
    for path in sorted(folder.rglob("*.dyad")):
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError):
            continue
        parts = path.parent.relative_to(folder).parts
        for match in _HEADER.finditer(text):
            line = text.count("\n", 0, match.start(1)) + 1
            column = match.start(1) - (text.rfind("\n", 0, match.start(1)) + 1) + 1
            found.setdefault((*parts, match.group(1)), (path, line, column))
    return found


def _spellings(names: dict[tuple[str, ...], tuple[Path, int, int]]) -> set[tuple[str, ...]]:
    """Each definition key with its flat spelling (`P.S.X` is also `P.X`, the library's alias
    rule): a user's flat `Position` names the shipped `Sources.Position`."""
    return set(names) | {key[-1:] for key in names}


def check_user_packages(roots: Sequence[Root]) -> None:
    """A note for each user package that replaces a shipped one; a located error for a user folder
    that only adds definitions to a shipped package (a package is found in one folder only)."""
    shipped = [root for root in roots if root.origin == "shipped library"]
    if not shipped:
        return
    shipped_folder = shipped[0].path
    for package in sorted(p.name for p in shipped_folder.iterdir()
                          if p.is_dir() and not p.name.startswith(("_", "."))):
        user = package_provider(roots, package)
        if package == BASE_PACKAGE or user is None or user.origin not in USER_ORIGINS:
            continue
        folder = user.path / package
        if not _is_julia_project(folder):
            added = _definition_names(folder)
            if added and not _spellings(added) & _spellings(_definition_names(shipped_folder / package)):
                raise _adds_to_shipped_error(package, folder, shipped_folder / package, added)
        warnings.warn(PackageNote(f"note: package `{package}` from {folder} replaces the shipped "
                                  f"one in {shipped_folder / package} (a package is found in one "
                                  f"folder; nothing of the shipped one is used)"), stacklevel=1)


def _is_julia_project(folder: Path) -> bool:
    """`folder` has a Project.toml, or is the `dyad/` folder of a Julia project that has one."""
    if (folder / PROJECT_FILE).is_file():
        return True
    resolved = folder.resolve()
    return resolved.name == "dyad" and (resolved.parent / PROJECT_FILE).is_file()


def _adds_to_shipped_error(package: str, folder: Path, shipped: Path,
                           added: dict[tuple[str, ...], tuple[Path, int, int]]) -> DyadError:
    path, line, column = min(added.values())
    name = next(key for key, where in added.items() if where == (path, line, column))[-1]
    return DyadError(
        f"`{name}` is added to package `{package}`, which ships with dyadc ({shipped}); a package is "
        f"found in one folder, so {folder} would replace the whole shipped `{package}`",
        Span(str(path), line, column, line, column + len(name) - 1),
        hint=f"make a package of your own: move {folder} to {folder.parent / ('My' + package)} and "
             f"name `{package}.X` qualified from it for the shipped components (or add a "
             f"{PROJECT_FILE} to {folder} if it is meant to replace the shipped `{package}`)")


def describe(roots: Sequence[Root]) -> str:
    """`path (origin), ...` for error messages."""
    return ", ".join(f"{root.path} ({root.origin})" for root in roots)



def project_dependencies(text: str, project: Path, package: str) -> set[str] | None:
    """The [deps] names of package `package`'s Project.toml (`text`, read from `project`), or
    None when it has none or declares no [deps]; TOML it cannot read is a located error."""
    if not text:
        return None
    import tomllib
    try:
        deps = tomllib.loads(text).get("deps")
    except tomllib.TOMLDecodeError as err:
        at = re.search(r"at line (\d+), column (\d+)", str(err))
        line, column = (int(at[1]), int(at[2])) if at else (1, 1)
        raise DyadError(f"package `{package}` has a {PROJECT_FILE} that is not TOML: "
                        f"{str(err).split(' (at ')[0]}", Span(str(project), line, column, line, column),
                        hint="its [deps] table lists the packages it may name") from None
    return set(deps) if isinstance(deps, dict) else None
