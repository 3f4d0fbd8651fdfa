"""Model specs: the component a command line or API call names, as `path/File.dyad`,
`path/File.dyad:Name` or a qualified name on the library path (the flat path of a definition
that lives in a subpackage is accepted too: compiler.model.library, `find_aliased`)."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Sequence

from compiler.errors import DyadError
from compiler.model.library import Library, Resolved, qualify
from compiler.model.library_path import LIBRARY_PATH_VARIABLE, describe
from compiler.syntax import ast


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
    found = library.find(spec) or library.find_aliased(spec)
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


def definitions_under(library: Library, folder: str | os.PathLike,
                      errors: list[DyadError] | None = None) -> list[Resolved]:
    """Every definition in the .dyad files below `folder` (parses them all), sorted by name.
    With `errors`, a file that does not parse is added to it and the others are still read."""
    folder = Path(folder).resolve()
    out: list[Resolved] = []
    for path in sorted(folder.rglob("*.dyad")):
        package = library.package_of_file(path)
        if package is None:
            package = ".".join(path.parent.relative_to(folder).parts)
        try:
            parsed = library.parse(path)
        except DyadError as err:
            if errors is None:
                raise
            errors.append(err)
            continue
        for definition in parsed.definitions:
            out.append(Resolved(qualify(package, definition.name), definition, package, parsed))
    return sorted(out, key=lambda r: r.qualified_name)
