"""The sources of a library: its search path (compiler.model.library_path), which root provides each
top-level package and what that package's Project.toml lets it use, and each file read and parsed
once. The base of compiler.model.library.Library, which finds definitions in these sources."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Callable, Sequence

from compiler.model.library_path import LIBRARY_PATH_VARIABLE, PROJECT_FILE, Root, \
    check_user_packages, package_provider, project_dependencies, search_path
from compiler.syntax import ast


def _default_parser() -> Callable[[str], ast.File]:
    from compiler.syntax.parser import parse_file
    return parse_file


class LibrarySources:
    def __init__(self, lib_dirs: Sequence[str | os.PathLike] = (), *, include_shipped: bool = True,
                 use_env: bool = True, parser: Callable[[str], ast.File] | None = None):
        self.search_path: list[Root] = search_path(lib_dirs, include_shipped=include_shipped,
                                                   use_env=use_env)
        self.roots: list[Path] = [root.path for root in self.search_path]
        self.parse_count = 0
        self._parser = parser
        self._files: dict[Path, ast.File] = {}
        self._texts: dict[Path, str] = {}
        self._providers: dict[str, Root | None] = {}  # top-level package -> the root providing it
        self._dependencies: dict[str, set[str] | None] = {}   # top-level package -> its [deps]

    def parse(self, path: str | os.PathLike) -> ast.File:
        path = Path(path).resolve()
        cached = self._files.get(path)
        if cached is not None:
            return cached
        if self._parser is None:
            self._parser = _default_parser()
        parsed = self._parser(str(path))
        self.parse_count += 1
        self._files[path] = parsed
        return parsed

    def source_text(self, path: Path) -> str:
        """The text of a source file (empty if unreadable), read once."""
        text = self._texts.get(path)
        if text is None:
            try:
                text = path.read_text(encoding="utf-8")
            except (OSError, UnicodeDecodeError):
                text = ""
            self._texts[path] = text
        return text

    def parsed_files(self) -> list[ast.File]:
        """The files parsed so far."""
        return list(self._files.values())

    def package_of_file(self, path: str | os.PathLike) -> str | None:
        """The namespace of a file under one of the roots, or None if it is under none."""
        path = Path(path).resolve()
        for root in self.roots:
            try:
                rel = path.parent.relative_to(root)
            except ValueError:
                continue
            return ".".join(rel.parts)
        return None

    def add_source_root(self, folder: str | os.PathLike) -> bool:
        """Search `folder` last, for .dyad sources only: its Python plugins are never executed
        (it was not named with -L or DYADC_PATH; see docs/security.md). False if it is searched
        already."""
        folder = Path(folder).resolve()
        if folder in self.roots:
            return False
        root = Root(folder, "model folder", runs_code=False)
        check_user_packages([*self.search_path, root])
        self.search_path.append(root)
        self.roots.append(folder)
        self._providers.clear()
        self._dependencies.clear()
        return True

    def provider(self, package: str) -> Root | None:
        """The root whose folder provides all of top-level package `package` (one root only)."""
        if package not in self._providers:
            self._providers[package] = package_provider(self.search_path, package)
        return self._providers[package]

    def roots_for(self, qualified_name: str) -> list[Path]:
        """The roots that may define `qualified_name`: its package's one provider, or every root
        for a name at the top level."""
        head, dot, _ = qualified_name.partition(".")
        if not dot:
            return list(self.roots)
        provider = self.provider(head)
        return [provider.path] if provider is not None else []

    def declared_dependencies(self, package: str) -> set[str] | None:
        """The [deps] of top-level package `package`'s Project.toml, or None when it declares none."""
        if package not in self._dependencies:
            self._dependencies[package] = self._read_dependencies(package)
        return self._dependencies[package]

    def _read_dependencies(self, package: str) -> set[str] | None:
        provider = self.provider(package) if package else None
        if provider is None:
            return None
        project = provider.path / package / PROJECT_FILE
        return project_dependencies(self.source_text(project), project, package)

    @property
    def user_roots(self) -> list[Path]:
        """The roots the user named (-L, DYADC_PATH), in order."""
        return [root.path for root in self.search_path if root.origin in ("-L", LIBRARY_PATH_VARIABLE)]
