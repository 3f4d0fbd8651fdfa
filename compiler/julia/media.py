"""Which medium a `path` connector field carries: the value of the `path` declaration joined to it
by `connect` (connectors with path fields) and `continuity` relations, built from the package's
Julia struct (compiler/julia/methods.py) with the declaration's keyword arguments over the
struct's defaults. Read from the instance tree; nothing is modified."""
from __future__ import annotations

import weakref
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

from compiler.errors import DyadError, Note
from compiler.julia.functions import UnreadableFunction, julia_source_files
from compiler.julia.methods import JuliaDefinitions, JuliaStruct, pick_method, \
    read_julia_definitions
from compiler.syntax import ast

_JOINS: "weakref.WeakKeyDictionary[Any, _Joins]" = weakref.WeakKeyDictionary()
_DEFINITIONS: dict[tuple, JuliaDefinitions] = {}


@dataclass(frozen=True)
class Medium:
    struct: JuliaStruct
    values: dict[str, Any]              # field -> value (sympy number or Boolean)
    definitions: JuliaDefinitions
    package: str

    def method(self, function: str, position: int, span):
        short = function.rpartition(".")[2]
        methods = self.definitions.methods.get(f"{self.package}.{short}", ())
        found = pick_method(methods, self.struct, position)
        if found is None:
            raise DyadError(f"`{short}` has no method for a medium of type "
                            f"`{self.struct.name.rpartition('.')[2]}` that dyadc can read", span,
                            notes=[Note(f"the medium's struct is defined in {self.struct.file}:"
                                        f"{self.struct.line}")])
        if isinstance(found, UnreadableFunction):
            raise found.error(span)
        return found


class _Joins:
    """Union of the path fields of one model, with the `path` declarations that give values."""

    def __init__(self, root: Any):
        self.parent: dict[str, str] = {}
        self.declared: dict[str, tuple[ast.TypedDecl, Any]] = {}
        for instance in _instances(root):
            self._read(instance)

    def find(self, key: str) -> str:
        while self.parent.get(key, key) != key:
            key = self.parent[key]
        return key

    def union(self, keys: list[str]) -> None:
        roots = [self.find(k) for k in keys]
        for other in roots[1:]:
            self.parent[other] = roots[0]

    def declaration(self, key: str):
        wanted = self.find(key)
        for name, found in self.declared.items():
            if self.find(name) == wanted:
                return found
        return None

    def _read(self, instance: Any) -> None:
        definition = instance.resolved.definition
        for decl in getattr(definition, "declarations", ()):
            if isinstance(decl, ast.TypedDecl) and decl.kind == "path" and decl.value is not None:
                self.declared[_join(instance.path, decl.name)] = (decl, instance)
        for relation, scope in instance.relations:
            if isinstance(relation, ast.Continuity):
                self.union([_join(scope.node.path, ref.dotted) for ref in relation.refs
                            if isinstance(ref, ast.Ref)])
            elif isinstance(relation, ast.Connect):
                by_field: dict[str, list[str]] = {}
                for ref in relation.refs:
                    connector = _walk(scope.node, ref)
                    for field_name in getattr(connector, "path_fields", {}):
                        by_field.setdefault(field_name, []).append(_join(connector.path, field_name))
                for keys in by_field.values():
                    self.union(keys)


def medium_of(node: Any, field: str, lexical: Any,
              evaluate_in: Callable[[ast.Expr, Any], Any]) -> Medium | None:
    """The medium that `field` (a dotted path field name, seen from `node`) carries, or None
    when no `path` declaration with a value is joined to it."""
    root = node
    while getattr(root, "parent", None) is not None:
        root = root.parent
    joins = _JOINS.get(root)
    if joins is None:
        joins = _JOINS[root] = _Joins(root)
    found = joins.declaration(_join(node.path, field))
    if found is None:
        return None
    decl, instance = found
    value = decl.value
    if not isinstance(value, ast.Call):
        raise DyadError(f"medium `{decl.name}`: dyadc reads a medium given as a constructor call "
                        f"such as `Water(density = 1000)`", decl.span)
    file = instance.resolved.file
    folder, package = _medium_package(value.function, instance, lexical.library)
    definitions = _definitions(folder, package)
    struct = definitions.structs.get(f"{package}.{value.function.rpartition('.')[2]}")
    if struct is None:
        raise DyadError(f"medium `{decl.name}`: `{value.function}` is not a Julia struct of "
                        f"package {package} (its src/*.jl)", value.span)
    if isinstance(struct, UnreadableFunction):
        raise DyadError(f"medium `{decl.name}`: {struct.reason}", value.span,
                        notes=[Note(f"defined in {struct.file}:{struct.line}")])
    scope = instance.scope(type(lexical)(lexical.library, instance.resolved.package, file))
    given = {kw.name: kw.value for kw in value.kwargs}
    unknown = sorted(set(given) - {name for name, _ in struct.fields})
    if unknown or value.args:
        raise DyadError(f"medium `{decl.name}`: struct `{value.function}` takes its fields by "
                        f"name" + (f"; it has no field `{unknown[0]}`" if unknown else ""),
                        value.span)
    values = {}
    for name, default in struct.fields:
        expr = given.get(name, default)
        if expr is None:
            raise DyadError(f"medium `{decl.name}`: field `{name}` of `{value.function}` has no "
                            f"value", value.span)
        values[name] = evaluate_in(expr, scope)
    return Medium(struct, values, definitions, package)


def _medium_package(constructor: str, instance: Any, library: Any) -> tuple[Path, str]:
    """The folder and name of the top-level package whose Julia sources define a medium's struct:
    the package a qualified constructor names (`HydraulicComponents.IsothermalCompressible`,
    from a model of any package), else the declaring file's own top-level package; for a file
    given by path, the project whose `dyad/` folder holds it."""
    head = (constructor if "." in constructor else instance.resolved.package or "").split(".")[0]
    provider = library.provider(head) if head else None
    if provider is not None and (provider.path / head).is_dir():
        return provider.path / head, head
    folder = Path(instance.resolved.file.path).parent
    return folder, instance.resolved.package or folder.resolve().parent.name.removesuffix(".jl")


def _definitions(folder: Path, package: str) -> JuliaDefinitions:
    paths = julia_source_files(folder)
    key = (str(folder.resolve()), package, tuple((str(p), p.stat().st_mtime_ns) for p in paths))
    found = _DEFINITIONS.get(key)
    if found is None:
        found = _DEFINITIONS[key] = read_julia_definitions(paths, package)
    return found


def _instances(root: Any):
    stack = [root]
    while stack:
        instance = stack.pop()
        yield instance
        for child in getattr(instance, "children", {}).values():
            if hasattr(child, "flat"):          # an array of instances
                stack.extend(c for c in child.flat if hasattr(c, "relations"))
            elif hasattr(child, "relations"):
                stack.append(child)


def _walk(node: Any, ref: ast.Ref) -> Any:
    for part in ref.parts:
        if part.indices:
            return None
        node = getattr(node, "children", {}).get(part.name)
        if node is None:
            return None
    return node


def _join(parent: str, name: str) -> str:
    return f"{parent}.{name}" if parent else name
