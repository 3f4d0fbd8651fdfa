"""Typed AST of definitions (components, connectors, types, enums, functions, structs,
analyses) and of a whole file. Metadata JSON is kept as a canonical JSON string
(`json.dumps(obj, sort_keys=True)`) to stay hashable; `metadata_dict()` reads it."""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Union

from compiler.errors import DyadError, Span
from compiler.syntax.ast_declarations import Declaration, Extends, TypeSpec, TypedDecl
from compiler.syntax.ast_expressions import NO_SPAN
from compiler.syntax.ast_relations import Relation


def metadata_dict(metadata: str | None) -> dict:
    return json.loads(metadata) if metadata else {}


@dataclass(frozen=True)
class ConnectorField:
    name: str
    kind: str                                   # 'potential' | 'flow' | 'input' | 'output' | 'stream' | 'path'
    type: TypeSpec
    doc: str | None = None
    metadata: str | None = None
    span: Span | None = NO_SPAN
    link: str | None = None
    value: "Expr | None" = None                 # a `path` field's default: `path medium::M = Water()`


@dataclass(frozen=True)
class ConnectorDef:
    name: str
    fields: tuple[ConnectorField, ...]
    partial: bool = False
    doc: str | None = None
    metadata: str | None = None
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class SignalConnectorDef:
    """`connector RealInput = input Real` (optionally with type modifiers / dims)."""
    name: str
    causality: str                              # 'input' | 'output'
    type: TypeSpec
    doc: str | None = None
    metadata: str | None = None
    span: Span | None = NO_SPAN
    link: str | None = None


@dataclass(frozen=True)
class TypeDef:
    """`type Length = Real(units = "m")`."""
    name: str
    base: TypeSpec
    doc: str | None = None
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class EnumDef:
    name: str
    members: tuple[str, ...]
    doc: str | None = None
    span: Span | None = NO_SPAN
    # Per member, the fields it carries (`| Oil(density::Real = 900)`); () when none has any.
    fields: tuple[tuple[TypedDecl, ...], ...] = ()


@dataclass(frozen=True)
class FunctionParam:
    name: str | None
    type: TypeSpec


@dataclass(frozen=True)
class FunctionTypeDef:
    """`type RealFunction = func(::Real)::Real`: the type of a function-valued parameter."""
    name: str
    params: tuple[FunctionParam, ...]
    result: TypeSpec
    doc: str | None = None
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class StructDef:
    """`struct Name  field::Type = default ... end`: a record of named values."""
    name: str
    fields: tuple[TypedDecl, ...]
    doc: str | None = None
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class ComponentDef:
    name: str
    extends: tuple[Extends, ...] = ()
    declarations: tuple[Declaration, ...] = ()
    relations: tuple[Relation, ...] = ()
    partial: bool = False
    prefix: str | None = None                   # None | 'example' | 'test'
    doc: str | None = None
    metadata: str | None = None
    span: Span | None = NO_SPAN
    # `external component`: behaviour implemented outside Dyad (in Julia); only its interface here
    external: bool = False


@dataclass(frozen=True)
class AnalysisDef:
    """`analysis Name extends TransientAnalysis(stop = 10, ...) ... end` (tier B; kept, not run)."""
    name: str
    extends: tuple[Extends, ...] = ()
    declarations: tuple[Declaration, ...] = ()
    relations: tuple[Relation, ...] = ()
    partial: bool = False
    doc: str | None = None
    metadata: str | None = None
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class Using:
    """`using Package: a, b` or `using Package`; `level` counts the leading dots of a relative
    `using .Sub` (1) or `using ..Sibling` (2), whose `package` is the name after the dots.
    `aliases[i]` is the name `names[i]` has in the file (`using P: a as b`), `()` for no renaming."""
    package: str
    names: tuple[str, ...] = ()
    span: Span | None = NO_SPAN
    level: int = 0
    aliases: tuple[str, ...] = ()

    def __post_init__(self):
        if self.aliases == self.names:      # no renaming: one spelling, so equal ASTs compare equal
            object.__setattr__(self, "aliases", ())

    @property
    def local_names(self) -> tuple[str, ...]:
        """The names this `using` brings into the file, after any renaming."""
        return self.aliases or self.names

    def imported(self, local: str) -> str | None:
        """The package's own name for `local` as the file writes it: through a rename
        (`using P: a as b` reads `b` as `a`), itself for a listed name or for any name when
        nothing is listed (`using P`), None when this `using` does not bring it in."""
        if not self.names:
            return local
        for name, alias in zip(self.names, self.local_names):
            if alias == local:
                return name
        return None

    @property
    def listed(self) -> str:
        """The names as written after the colon: `a, b as c`."""
        return ", ".join(name if name == alias else f"{name} as {alias}"
                         for name, alias in zip(self.names, self.local_names))

    @property
    def written(self) -> str:
        """The package as written: `..Sibling`."""
        return "." * self.level + self.package

    def absolute_package(self, within: str) -> str:
        """The package this names from a file of package `within`, as Julia reads a relative
        path: `.` is `within` itself, each further dot one enclosing package up, and above the
        top-level package are the top-level packages (`using ..Other` in package `P`)."""
        if not self.level:
            return self.package
        parts = within.split(".") if within else []
        base = parts[:max(len(parts) - (self.level - 1), 0)]
        if self.level - 1 > len(parts):
            raise DyadError(f"`using {self.written}` goes {self.level - 1} package level(s) up from "
                            f"`{within or 'the top level'}`, above the top-level packages", self.span,
                            hint=f"name the package absolutely: `using {self.package}`")
        return ".".join(base + [self.package])


Definition = Union[ComponentDef, ConnectorDef, SignalConnectorDef, TypeDef, EnumDef, AnalysisDef,
                   FunctionTypeDef, StructDef]


@dataclass(frozen=True)
class File:
    path: str = field(compare=False)
    usings: tuple[Using, ...] = ()
    definitions: tuple[Definition, ...] = ()
    span: Span | None = NO_SPAN
