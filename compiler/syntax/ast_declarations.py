"""Typed AST of declarations: parameters, variables, components, extends, modifications."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Union

from compiler.errors import Span
from compiler.syntax.ast_expressions import NO_SPAN, Expr, Iterator


@dataclass(frozen=True)
class Modification:
    """One modifier: `m = 2`, `phi(initial = 0.3)`, `final k = 1`, `x(guess = 1) = 2`.

    `name` may be dotted (`body.m = 2`). `value` is None when only nested modifiers are given.
    """
    name: str
    value: "Expr | None" = None
    nested: tuple["Modification", ...] = ()
    final: bool = False
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class TypeSpec:
    """`Real`, `Length`, `Real(units = "m", guess = 1)`, `Real[2]`, `Real[n, 3]`."""
    name: str                                   # possibly qualified: `Pkg.Length`
    modifications: tuple[Modification, ...] = ()
    dims: tuple["Expr", ...] = ()
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class ParameterDecl:
    name: str
    type: TypeSpec
    default: "Expr | None" = None
    variability: str = "parameter"              # 'parameter' | 'structural' | 'constant'
    final: bool = False
    doc: str | None = None
    metadata: str | None = None
    condition: "Expr | None" = None             # `... if flag`
    span: Span | None = NO_SPAN
    link: str | None = None                     # `{^name}`: the entry in the definition's "_links"


@dataclass(frozen=True)
class VariableDecl:
    name: str
    type: TypeSpec
    binding: "Expr | None" = None               # `= expr` adds the equation name = expr
    initial: "Expr | None" = None               # `= initial expr` sets only the initial value
    causality: str | None = None                # None | 'input' | 'output'
    doc: str | None = None
    metadata: str | None = None
    condition: "Expr | None" = None
    span: Span | None = NO_SPAN
    link: str | None = None


@dataclass(frozen=True)
class ComponentDecl:
    """A subcomponent: `body = Body(m = 2)`, or an array `links = [Link(L = l[i]) for i in 1:n]`."""
    name: str
    type_name: str                              # possibly qualified
    modifications: tuple[Modification, ...] = ()
    iterators: tuple[Iterator, ...] = ()        # non-empty for component arrays
    doc: str | None = None
    metadata: str | None = None
    condition: "Expr | None" = None
    span: Span | None = NO_SPAN
    link: str | None = None


@dataclass(frozen=True)
class Extends:
    type_name: str
    modifications: tuple[Modification, ...] = ()
    metadata: str | None = None
    span: Span | None = NO_SPAN
    doc: str | None = None
    link: str | None = None


@dataclass(frozen=True)
class TypedDecl:
    """`name::Type = value` without a keyword: analysis fields (`model::M = M()`), struct and enum
    fields, replaceable components; with `kind` 'path' or 'stream' a fluid-medium declaration
    (`path medium::Medium = Water()`). Kept as written; instantiation does not use them yet."""
    name: str
    type: TypeSpec
    value: "Expr | None" = None
    kind: str | None = None                     # None | 'path' | 'stream'
    doc: str | None = None
    metadata: str | None = None
    condition: "Expr | None" = None
    span: Span | None = NO_SPAN
    link: str | None = None


Declaration = Union[ParameterDecl, VariableDecl, ComponentDecl, TypedDecl]
