"""The library: finds definitions by qualified name, parsing only the files it needs.

Roots (compiler.model.library_path): the library shipped with dyadc, each `-L DIR` (`lib_dirs`),
each folder of the environment variable DYADC_PATH; then, source-only, the folder of a model file
given by path. A top-level package is one unit found in one root (`package_provider`: a user's
package replaces the shipped one); names at the top level are searched in every root, in order.
Names used inside package P resolve in P (innermost subpackage first), then qualified by a package
P may use (any package on the path, or only those of P's Project.toml [deps] when it declares
them), then in the base library `Dyad`; an unqualified name never leaves P and the base library.
Folders are namespaces: `root/A/B/Name.dyad` defines `A.B.Name`; when
no file is named after the definition, the other `.dyad` files of the folder are searched (a cheap
text scan decides which ones are worth parsing). Every parsed file is cached; `parse_count` counts
real parses (tests use it to check laziness). Python function plugins (`dyad_functions.py`) are
executed only from roots on the search path, never from a source-only root.
"""
from __future__ import annotations

import os
import re
from dataclasses import dataclass
from typing import Callable, Sequence

from compiler.errors import DyadError, Span
from compiler.model.functions import GLOBAL_REGISTRY, FunctionRegistry
from compiler.model.library_functions import FUNCTION_PLUGIN_FILE, FunctionLookup
from compiler.model.library_path import BASE_PACKAGE
from compiler.model.library_sources import LibrarySources
from compiler.model.library_suggest import DEFINITION_KEYWORDS, PRIMITIVE_TYPES, \
    unsupported_component_error, suggest_component, suggest_type
from compiler.syntax import ast

__all__ = ["FUNCTION_PLUGIN_FILE", "PRIMITIVE_TYPES", "Library", "Resolved", "qualify"]

STANDARD_PACKAGE = BASE_PACKAGE


@dataclass(frozen=True)
class Resolved:
    """A definition together with where it was written (for resolving the names it uses)."""
    qualified_name: str
    definition: ast.Definition
    package: str
    file: ast.File

    @property
    def name(self) -> str:
        return self.definition.name


def qualify(package: str, name: str) -> str:
    return f"{package}.{name}" if package else name


class Library(LibrarySources, FunctionLookup):
    """Definitions by qualified name, and the name a use inside a package means (the rules above),
    in the sources of compiler.model.library_sources; functions by compiler.model.library_functions."""

    def __init__(self, lib_dirs: Sequence[str | os.PathLike] = (), *, include_shipped: bool = True,
                 use_env: bool = True, parser: Callable[[str], ast.File] | None = None,
                 registry: FunctionRegistry = GLOBAL_REGISTRY):
        super().__init__(lib_dirs, include_shipped=include_shipped, use_env=use_env, parser=parser)
        self.registry = registry
        self._found: dict[str, Resolved | None] = {}
        self._aliased: dict[str, Resolved | None] = {}
        self._subfolders: dict[str, list[str]] = {}
        self._lookup_cache: dict[tuple, Resolved | None] = {}
        self.type_cache: dict[tuple, object] = {}     # used by compiler.model.instantiate
        self._julia: dict[str, dict] = {}             # package folder -> its Julia functions

    def add_source_root(self, folder: str | os.PathLike) -> bool:
        """LibrarySources.add_source_root, forgetting every lookup made without `folder`."""
        added = super().add_source_root(folder)
        if added:
            self._found.clear()
            self._aliased.clear()
            self._subfolders.clear()
            self._lookup_cache.clear()
        return added

    # --------------------------------------------------------------------------- lookup

    def find(self, qualified_name: str) -> Resolved | None:
        """The definition with this fully qualified name, or None."""
        if qualified_name in self._found:
            return self._found[qualified_name]
        result = self._search(qualified_name)
        self._found[qualified_name] = result
        return result

    def _search(self, qualified_name: str) -> Resolved | None:
        *package_parts, name = qualified_name.split(".")
        package = ".".join(package_parts)
        header = re.compile(rf"(?<![\w.]){DEFINITION_KEYWORDS}\s+{re.escape(name)}(?![\w])")
        for root in self.roots_for(qualified_name):
            folder = root.joinpath(*package_parts)
            named = folder / f"{name}.dyad"
            try:
                if not folder.is_dir():
                    continue
                candidates = [named] if named.is_file() else []
            except OSError:         # a part longer than a file name may be (ENAMETOOLONG) names no file
                continue
            # under a resolved root already: a resolve() per scanned file cost a compile 20 ms;
            # the plain substring test first spares the header pattern most texts (30 ms)
            candidates += [p for p in sorted(folder.glob("*.dyad"))
                           if p != named and name in self.source_text(p) and header.search(self.source_text(p))]
            for path in candidates:
                parsed = self.parse(path)
                for definition in parsed.definitions:
                    if definition.name == name:
                        return Resolved(qualified_name, definition, package, parsed)
        return None

    def candidates(self, name: str, package: str, file: ast.File | None) -> list[str]:
        """Qualified names to try for `name` used inside `package`, innermost first."""
        out: list[str] = []
        parts = package.split(".") if package else []
        for k in range(len(parts), 0, -1):
            out.append(".".join(parts[:k]) + "." + name)
        head = name.split(".", 1)[0]
        for using in (file.usings if file else ()):
            imported = using.imported(head)         # `using P: a as b` reads `b.x` as `P.a.x`
            if imported is not None:
                out.append(f"{using.absolute_package(package)}.{imported}{name[len(head):]}")
        if "." in name or not package:       # an unqualified name never leaves its package
            out.append(name)
        out.append(f"{STANDARD_PACKAGE}.{name}")
        usable = self._usable_packages(package)
        seen: set[str] = set()
        return [c for c in out if not (c in seen or seen.add(c))
                and (usable is None or c.split(".", 1)[0] in usable or "." not in c)]

    def _usable_packages(self, package: str) -> set[str] | None:
        """The top-level packages names inside `package` may resolve into, or None for any: its
        own, its declared dependencies and the base library when its Project.toml declares deps."""
        head = package.split(".", 1)[0]
        deps = self.declared_dependencies(head)
        return None if deps is None else deps | {head, STANDARD_PACKAGE}

    def lookup(self, name: str, package: str, file: ast.File | None,
               kinds: tuple[type, ...] = ()) -> Resolved | None:
        """The definition `name` means inside `package` (and `file`). With `kinds`, a definition of
        another kind is passed over for a later candidate (a type position skips the component
        `TranslationalComponents.Position` for the type `Dyad.Position`); if no candidate is of
        those kinds, the first found is returned (its use reports the mismatch). Only when no
        candidate names a definition are the candidates read as flat paths (`find_aliased`), so
        an alias never shadows a definition found by its own path."""
        key = (package, id(file), name, kinds)
        if key in self._lookup_cache:
            return self._lookup_cache[key]
        found = []
        if file is not None and "." not in name:
            found = [Resolved(qualify(package, name), definition, package, file)
                     for definition in file.definitions if definition.name == name][:1]
        result = (self._first_found(name, package, file, kinds, found, self.find)
                  or self._first_found(name, package, file, kinds, [], self.find_aliased))
        self._lookup_cache[key] = result
        return result

    def _first_found(self, name: str, package: str, file: ast.File | None, kinds: tuple[type, ...],
                     found: list[Resolved], finder: Callable[[str], Resolved | None]) -> Resolved | None:
        for candidate in self.candidates(name, package, file):
            if found and (not kinds or isinstance(found[-1].definition, kinds)):
                break
            result = finder(candidate)
            if result is not None:
                found.append(result)
        chosen = [r for r in found if isinstance(r.definition, kinds)] if kinds else []
        return (chosen or found or [None])[0]

    def find_aliased(self, qualified_name: str) -> Resolved | None:
        """The definition a flat path `P.X` names when no folder defines it but exactly one
        subpackage of P, at any depth, does (`BlockComponents.LimPID` for
        `BlockComponents.Continuous.LimPID`, `ElectricalComponents.Resistor` for
        `ElectricalComponents.Analog.Basic.Resistor`): Dyad's documentation names the standard
        library by subpackage, its published repositories by the flat path. The one alias rule:
        the library holds each component once, at its documented path."""
        if qualified_name not in self._aliased:
            defined = self.subpackage_definitions(qualified_name)
            self._aliased[qualified_name] = defined[0] if len(defined) == 1 else None
        return self._aliased[qualified_name]

    def subpackage_definitions(self, qualified_name: str) -> list[Resolved]:
        """The definitions `P.S.X` (`P.S.T.X`, ...) of the subpackages of P at any depth, for
        `P.X` that no folder of P defines (none for a name at the top level)."""
        package, _, name = qualified_name.rpartition(".")
        if not package or self.find(qualified_name) is not None:
            return []
        found = (self.find(f"{sub}.{name}") for sub in self.nested_subpackages(package))
        return [definition for definition in found if definition is not None]

    def nested_subpackages(self, package: str) -> list[str]:
        """The qualified names of the subpackages of `package` at any depth, parents first."""
        out: list[str] = []
        pending = [package]
        while pending:
            parent = pending.pop(0)
            children = [f"{parent}.{sub}" for sub in self.subpackages(parent)]
            out += children
            pending += children
        return out

    def subpackages(self, package: str) -> list[str]:
        """The names of the direct subfolders of `package` in the roots that may define it."""
        if package in self._subfolders:
            return self._subfolders[package]
        names: set[str] = set()
        for root in self.roots_for(f"{package}.X"):
            folder = root.joinpath(*package.split("."))
            try:
                names.update(p.name for p in folder.iterdir()
                             if p.is_dir() and p.name.isidentifier() and not p.name.startswith("_"))
            except OSError:         # no such folder, or a name longer than a file name may be
                continue
        self._subfolders[package] = sorted(names)
        return self._subfolders[package]

    def resolve(self, name: str, package: str, file: ast.File | None, span: Span | None,
                what: str = "type", kinds: tuple[type, ...] = ()) -> Resolved:
        found = self.lookup(name, package, file, kinds)
        if found is None:
            if what == "component type" and (refused := unsupported_component_error(name, span)):
                raise refused
            suggest = suggest_component if what == "component type" else suggest_type
            raise DyadError(f"unknown {what} `{name}`", span, hint=suggest(self, name, package, file))
        return found
