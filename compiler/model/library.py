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
from pathlib import Path
from typing import Callable, Sequence

from compiler.errors import DyadError, Span, closest, suggest_name
from compiler.model.builtins import builtin, suggest_function
from compiler.model.functions import GLOBAL_REGISTRY, FunctionImpl, FunctionRegistry
from compiler.syntax.modelica_forms import modelica_form_error
from compiler.julia.functions import JuliaFunction, UnreadableFunction, julia_source_files, \
    read_julia_functions
from compiler.model.library_path import BASE_PACKAGE, LIBRARY_PATH_VARIABLE, PROJECT_FILE, Root, \
    check_user_packages, describe, package_provider, search_path
from compiler.syntax import ast

STANDARD_PACKAGE = BASE_PACKAGE
PRIMITIVE_TYPES = ("Real", "Integer", "Boolean", "String")
FUNCTION_PLUGIN_FILE = "dyad_functions.py"

_DEFINITION_KEYWORDS = r"(?:component|connector|type|enum|analysis|struct)"


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


def _default_parser() -> Callable[[str], ast.File]:
    from compiler.syntax.parser import parse_file
    return parse_file


def qualify(package: str, name: str) -> str:
    return f"{package}.{name}" if package else name


class Library:
    def __init__(self, lib_dirs: Sequence[str | os.PathLike] = (), *, include_shipped: bool = True,
                 use_env: bool = True, parser: Callable[[str], ast.File] | None = None,
                 registry: FunctionRegistry = GLOBAL_REGISTRY):
        self.search_path: list[Root] = search_path(lib_dirs, include_shipped=include_shipped,
                                                   use_env=use_env)
        self.roots: list[Path] = [root.path for root in self.search_path]
        self.registry = registry
        self.parse_count = 0
        self._parser = parser
        self._files: dict[Path, ast.File] = {}
        self._texts: dict[Path, str] = {}
        self._found: dict[str, Resolved | None] = {}
        self._lookup_cache: dict[tuple, Resolved | None] = {}
        self.type_cache: dict[tuple, object] = {}     # used by compiler.model.instantiate
        self._julia: dict[str, dict] = {}             # package folder -> its Julia functions
        self._providers: dict[str, Root | None] = {}  # top-level package -> the root providing it
        self._dependencies: dict[str, set[str] | None] = {}   # top-level package -> its [deps]

    # -------------------------------------------------------------------------------- files

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

    def _text(self, path: Path) -> str:
        text = self._texts.get(path)
        if text is None:
            try:
                text = path.read_text(encoding="utf-8")
            except (OSError, UnicodeDecodeError):
                text = ""
            self._texts[path] = text
        return text

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

    def add_source_root(self, folder: str | os.PathLike) -> None:
        """Search `folder` last, for .dyad sources only: its Python plugins are never executed
        (it was not named with -L or DYADC_PATH; see docs/security.md)."""
        folder = Path(folder).resolve()
        if folder in self.roots:
            return
        root = Root(folder, "model folder", runs_code=False)
        check_user_packages([*self.search_path, root])
        self.search_path.append(root)
        self.roots.append(folder)
        self._found.clear()
        self._lookup_cache.clear()
        self._providers.clear()
        self._dependencies.clear()

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
        text = self._text(provider.path / package / PROJECT_FILE)
        if not text:
            return None
        import tomllib
        try:
            deps = tomllib.loads(text).get("deps")
        except tomllib.TOMLDecodeError as err:
            at = re.search(r"at line (\d+), column (\d+)", str(err))
            line, column = (int(at[1]), int(at[2])) if at else (1, 1)
            raise DyadError(f"package `{package}` has a {PROJECT_FILE} that is not TOML: "
                            f"{str(err).split(' (at ')[0]}",
                            Span(str(provider.path / package / PROJECT_FILE), line, column, line, column),
                            hint="its [deps] table lists the packages it may name") from None
        return set(deps) if isinstance(deps, dict) else None

    @property
    def user_roots(self) -> list[Path]:
        """The roots the user named (-L, DYADC_PATH), in order."""
        return [root.path for root in self.search_path if root.origin in ("-L", LIBRARY_PATH_VARIABLE)]

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
        header = re.compile(rf"(?<![\w.]){_DEFINITION_KEYWORDS}\s+{re.escape(name)}(?![\w])")
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
                           if p != named and name in self._text(p) and header.search(self._text(p))]
            for path in candidates:
                parsed = self.parse(path)
                for definition in parsed.definitions:
                    if definition.name == name:
                        return Resolved(qualified_name, definition, package, parsed)
        return None

    def _candidates(self, name: str, package: str, file: ast.File | None) -> list[str]:
        """Qualified names to try for `name` used inside `package`, innermost first."""
        out: list[str] = []
        parts = package.split(".") if package else []
        for k in range(len(parts), 0, -1):
            out.append(".".join(parts[:k]) + "." + name)
        head = name.split(".", 1)[0]
        for using in (file.usings if file else ()):
            if not using.names or head in using.names:
                out.append(f"{using.package}.{name}")
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
        those kinds, the first found is returned (its use reports the mismatch)."""
        key = (package, id(file), name, kinds)
        if key in self._lookup_cache:
            return self._lookup_cache[key]
        found = []
        if file is not None and "." not in name:
            found = [Resolved(qualify(package, name), definition, package, file)
                     for definition in file.definitions if definition.name == name][:1]
        for candidate in self._candidates(name, package, file):
            if found and (not kinds or isinstance(found[-1].definition, kinds)):
                break
            result = self.find(candidate)
            if result is not None:
                found.append(result)
        chosen = [r for r in found if isinstance(r.definition, kinds)] if kinds else []
        result = (chosen or found or [None])[0]
        self._lookup_cache[key] = result
        return result

    def resolve(self, name: str, package: str, file: ast.File | None, span: Span | None,
                what: str = "type", kinds: tuple[type, ...] = ()) -> Resolved:
        found = self.lookup(name, package, file, kinds)
        if found is None:
            suggest = self._suggest_component if what == "component type" else self._suggest_type
            raise DyadError(f"unknown {what} `{name}`", span, hint=suggest(name, package, file))
        return found

    def _suggest_component(self, name: str, package: str, file: ast.File | None) -> str | None:
        """In a component position only components are suggested (never a quantity type such as
        `Resistance`): those of the file, of the files parsed so far, and of the folders where
        `name` would be looked up, qualified as the user wrote `name`."""
        prefix, _, local = name.rpartition(".")
        known: set[str] = set()
        if not prefix:
            for parsed in ([file] if file else []) + list(self._files.values()):
                known.update(d.name for d in parsed.definitions if isinstance(d, ast.ComponentDef))
        header = re.compile(r"(?<![\w.])component\s+(\w+)")
        for candidate in self._candidates(name, package, file):
            for root in self.roots_for(candidate):
                folder = root.joinpath(*candidate.split(".")[:-1])
                try:
                    paths = sorted(folder.glob("*.dyad")) if folder.is_dir() else []
                except OSError:         # a name longer than a file name may be
                    continue
                for path in paths:
                    known.update(header.findall(self._text(path.resolve())))
        match = closest(local, known)
        return f"did you mean `{prefix + '.' if prefix else ''}{match[0]}`?" if match else None

    def _suggest_type(self, name: str, package: str, file: ast.File | None) -> str | None:
        known = set(PRIMITIVE_TYPES)
        if file is not None:
            known.update(d.name for d in file.definitions)
        for parsed in self._files.values():
            known.update(d.name for d in parsed.definitions)
        for root in self.roots_for(f"{STANDARD_PACKAGE}.{name}"):
            std = root / STANDARD_PACKAGE
            if std.is_dir():
                for path in std.glob("*.dyad"):
                    known.update(re.findall(rf"{_DEFINITION_KEYWORDS}\s+(\w+)",
                                            self._text(path.resolve())))
        return suggest_name(name.rsplit(".", 1)[-1], known)

    # ---------------------------------------------------------------------------- functions

    def resolve_function(self, name: str, package: str, file: ast.File | None,
                         span: Span | None) -> FunctionImpl | JuliaFunction:
        entry = builtin(name)
        if entry is not None and entry.function is not None:
            return entry.function
        candidates = self._candidates(name, package, file)
        for candidate in candidates:
            self._load_plugins_for(candidate)
            found = self.registry.get(candidate)
            if found is not None:
                return found
        found_julia = [self.julia_function(candidate) for candidate in candidates]
        if file is not None and "." not in name:
            # a file given by path from a project's dyad/ folder: its package's src/ is beside it
            found_julia.append(self.julia_function_beside(Path(file.path), name))
        for julia in found_julia:
            if isinstance(julia, UnreadableFunction):
                raise julia.error(span)
            if julia is not None:
                return julia
        skipped = [plugin for candidate in candidates for plugin in self._plugins_for(candidate, False)]
        if skipped:
            raise DyadError(f"unknown function `{name}`", span,
                            hint=f"{skipped[0]} was not run: dyadc runs a library's Python only "
                                 f"from folders named with -L DIR or {LIBRARY_PATH_VARIABLE}; if you "
                                 f"trust it, add -L {skipped[0].parent}")
        modelica = modelica_form_error(name, span)          # `pre(x)`, `edge(b)`
        if modelica is not None:
            raise modelica
        suggestion = suggest_function(name, self.registry)
        raise DyadError(f"unknown function `{name}`", span,
                        hint=f"did you mean `{suggestion}`?" if suggestion else None)

    def julia_function(self, qualified_name: str) -> JuliaFunction | UnreadableFunction | None:
        """A function `Pkg.name` that package `Pkg` defines in Julia (compiler.julia.functions),
        from the first root whose folder `Pkg` defines it, as for definitions."""
        package, _, name = qualified_name.rpartition(".")
        if not package or "." in package:
            return None
        for root in self.roots_for(qualified_name):
            if (root / package).is_dir():
                found = self._julia_functions(root / package, package).get(qualified_name)
                if found is not None:
                    return found
        return None

    def julia_function_beside(self, dyad_file: Path, name: str) -> JuliaFunction | UnreadableFunction | None:
        """`name` defined in Julia by the project whose dyad/ folder holds `dyad_file`."""
        folder = dyad_file.parent
        package = folder.resolve().parent.name.removesuffix(".jl")
        return self._julia_functions(folder, package).get(f"{package}.{name}")

    def _julia_functions(self, folder: Path, package: str) -> dict:
        key = str(folder.resolve())
        if key not in self._julia:
            functions: dict = {}
            for path in julia_source_files(folder):
                for qualified, value in read_julia_functions(path, package).items():
                    functions.setdefault(qualified, value)
            self._julia[key] = functions
        return self._julia[key]

    def _plugins_for(self, qualified_name: str, runs_code: bool) -> list[Path]:
        """The plugin files for the package of `qualified_name` in the roots that may (or may
        not) run code."""
        package_parts = qualified_name.split(".")[:-1]
        allowed = set(self.roots_for(qualified_name))
        plugins = (root.path.joinpath(*package_parts) / FUNCTION_PLUGIN_FILE
                   for root in self.search_path if root.runs_code == runs_code and root.path in allowed)
        return [plugin for plugin in plugins if plugin.is_file()]

    def _load_plugins_for(self, qualified_name: str) -> None:
        for plugin in self._plugins_for(qualified_name, True):
            try:
                self.registry.load_plugin(plugin)
            except Exception as exc:  # a broken plugin is a library error, not a crash
                raise DyadError(f"cannot load function plugin {plugin}: {exc}") from exc

    # ---------------------------------------------------------------------------- listing

    def definitions_under(self, folder: str | os.PathLike,
                          errors: list[DyadError] | None = None) -> list[Resolved]:
        """Every definition in the .dyad files below `folder` (parses them all), sorted by name.
        With `errors`, a file that does not parse is added to it and the others are still read."""
        folder = Path(folder).resolve()
        out: list[Resolved] = []
        for path in sorted(folder.rglob("*.dyad")):
            package = self.package_of_file(path)
            if package is None:
                package = ".".join(path.parent.relative_to(folder).parts)
            try:
                parsed = self.parse(path)
            except DyadError as err:
                if errors is None:
                    raise
                errors.append(err)
                continue
            for definition in parsed.definitions:
                out.append(Resolved(qualify(package, definition.name), definition, package, parsed))
        return sorted(out, key=lambda r: r.qualified_name)


# ------------------------------------------------------------------------------- model specs

def load_model(spec: str, lib_dirs: Sequence[str] = (), *,
               library: Library | None = None) -> tuple[Library, ast.ComponentDef, str]:
    """Find the component named by `spec`: `path/File.dyad`, `path/File.dyad:Name` or a qualified
    name on the library path. Returns the library (for further lookups), the definition and its
    qualified name."""
    library = library or Library(lib_dirs)
    resolved = resolve_model(spec, library)
    return library, resolved.definition, resolved.qualified_name


def split_file_spec(spec: str) -> tuple[str, str]:
    """`path/File.dyad:Name` -> (path/File.dyad, Name); any other spec -> (spec, "")."""
    file_part, _, name = spec.partition(":") if ".dyad:" in spec else (spec, "", "")
    return file_part, name


def parse_spec_file(file_part: str, library: Library, what: str = "file"):
    """The parsed source file a spec names and its package ("" outside the library path, whose
    folder is then searched for sibling sources, though its Python is not run: only folders the
    user named run code)."""
    path = Path(file_part)
    if not path.is_file():
        raise DyadError(f"{what} `{file_part}` not found")
    package = library.package_of_file(path)
    if package is None:
        library.add_source_root(path.resolve().parent)
        package = ""
    return library.parse(path), package


def resolve_model(spec: str, library: Library) -> Resolved:
    file_part, name = split_file_spec(spec)
    if file_part.endswith(".dyad"):
        path = Path(file_part)
        parsed, package = parse_spec_file(file_part, library, "model file")
        components = [d for d in parsed.definitions if isinstance(d, ast.ComponentDef)]
        if name:
            chosen = [d for d in components if d.name == name]
            if not chosen:
                raise DyadError(f"no component `{name}` in {file_part}", parsed.span,
                                hint=_choices(components))
        else:
            chosen = [d for d in components if d.name == path.stem]
            if not chosen:
                chosen = [d for d in components if not d.partial]
            if len(chosen) != 1:
                raise DyadError(f"{file_part} does not name one component; use "
                                f"`{file_part}:Name`", parsed.span, hint=_choices(components))
        definition = chosen[0]
        return Resolved(qualify(package, definition.name), definition, package, parsed)
    found = library.find(spec)
    if found is None:
        raise DyadError(f"no model `{spec}` on the library path ({describe(library.search_path)})",
                        hint=f"add the folder that holds its top-level package with -L DIR or "
                             f"{LIBRARY_PATH_VARIABLE}")
    if not isinstance(found.definition, ast.ComponentDef):
        raise DyadError(f"`{spec}` is not a component", found.definition.span)
    return found


def _choices(components: list[ast.ComponentDef]) -> str | None:
    if not components:
        return None
    return "components in the file: " + ", ".join(d.name for d in components)
