"""Rewrites inside the definition of a subcomponent: a model of the corpus is run with one of the
shipped library's components it instantiates (`resistor = ElectricalComponents.Resistor(...)`)
written another way. The package is copied beside the run and linked with `-L`, which replaces
the shipped package of its name (docs/compatibility.md); only rewrites that keep the
definition's interface apply (rewrites.INTERFACE_KEEPING)."""
from __future__ import annotations

import dataclasses
import random
import shutil
from pathlib import Path

from compiler.model.library import Library
from compiler.syntax import ast
from compiler.syntax.format import format_file
from compiler.syntax.parser import parse_file
from tests.metamorphic import rewrites
from tests.metamorphic.corpus import LIBRARY


@dataclasses.dataclass(frozen=True)
class SubcomponentRewrite:
    type_name: str           # the qualified name of the rewritten definition
    lib_dir: Path            # the folder holding the rewritten package (for -L)
    applied: list[str]       # the rewrites applied


_SHIPPED = Library(include_shipped=True)


def library_definitions(component: ast.ComponentDef) -> list[tuple[str, Path]]:
    """(qualified name, file) of each shipped-library definition `component` instantiates."""
    found = set()
    for d in component.declarations:
        if isinstance(d, ast.ComponentDecl) and "." in d.type_name:
            # the library's own lookup: a flat path names the definition at its documented one
            resolved = _SHIPPED.find(d.type_name) or _SHIPPED.find_aliased(d.type_name)
            if resolved is not None and Path(resolved.file.path).is_relative_to(LIBRARY):
                found.add((resolved.qualified_name, Path(resolved.file.path)))
    return sorted(found)


def rewrite_subcomponent(component: ast.ComponentDef, seed: int, folder: Path) -> SubcomponentRewrite | None:
    """One library definition `component` instantiates, drawn by `seed`, rewritten (by `seed`) in
    a copy of its package under `folder`; where no rewrite applies to the one drawn (a definition
    without equations of its own), the next in a seeded order; None where none can be rewritten."""
    candidates = library_definitions(component)
    if not candidates:
        return None
    rng = random.Random(seed)
    first = rng.choice(candidates)
    others = [c for c in candidates if c != first]
    rng.shuffle(others)
    for type_name, source in [first] + others:
        change = _rewritten_copy(type_name, source, seed, folder)
        if change is not None:
            return change
    return None


def _rewritten_copy(type_name: str, source: Path, seed: int, folder: Path) -> SubcomponentRewrite | None:
    """`type_name` (defined in `source`) rewritten by `seed` in a fresh copy of its package under
    `folder`; None (and no copy) where no interface-keeping rewrite applies to it."""
    package = type_name.split(".")[0]
    file = parse_file(source)
    name = type_name.split(".")[-1]
    (definition,) = [d for d in file.definitions if isinstance(d, ast.ComponentDef) and d.name == name]
    rewritten, applied = rewrites.rewrite(definition, seed, allowed=rewrites.INTERFACE_KEEPING)
    if not applied:
        return None
    target = folder / "lib" / package
    shutil.copytree(LIBRARY / package, target)
    path = target / source.relative_to(LIBRARY / package)
    definitions = tuple(rewritten.component if d is definition else d for d in file.definitions)
    path.write_text(format_file(dataclasses.replace(file, definitions=definitions)), encoding="utf-8")
    return SubcomponentRewrite(type_name, folder / "lib", applied)
