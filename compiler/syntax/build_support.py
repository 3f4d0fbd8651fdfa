"""Shared pieces of the parse-tree -> AST rules: spans, literal values, the small records that carry
partial results between rules, and how suffixes (metadata, links, conditions) are collected."""
from __future__ import annotations

import json
import math
from dataclasses import dataclass

from lark import Token

from compiler.errors import DyadError, Span
from compiler.syntax import ast

# Decimal exponents, so that `100n` is exactly the float of `100e-9`.
SI_EXPONENTS = {"p": -12, "n": -9, "u": -6, "μ": -6, "m": -3, "k": 3, "M": 6, "G": 9, "T": 12}
# An integer literal must fit a 64-bit float once lowered (1.8e308 has 309 digits).
MAX_INTEGER_DIGITS = 308

OPERATOR_SPELLINGS = {"||": "or", "&&": "and", "≤": "<=", "≥": ">=", "≠": "!="}


def token_span(tok: Token, filename: str) -> Span:
    return Span(filename, tok.line, tok.column, tok.end_line, max(tok.end_column - 1, tok.column))


def meta_span(meta, filename: str) -> Span | None:
    """The span of a parse-tree node's `meta`, or None for a node that covers no text."""
    if getattr(meta, "empty", True):
        return None
    return Span(filename, meta.line, meta.column, meta.end_line, max(meta.end_column - 1, 1))


def join_spans(first: Span | None, last: Span | None) -> Span | None:
    if first is None or last is None:
        return first or last
    return Span(first.file, first.line, first.column, last.end_line, last.end_column)


def string_content(raw: str) -> str:
    """The source text between the quotes, verbatim: escapes are not interpreted (see docs)."""
    if raw.startswith('"""'):
        return raw[3:-3]
    return raw[1:-1]


class LiteralError(ValueError):
    """A number literal that has no finite 64-bit value."""


def number_value(text: str) -> float | int:
    suffix = text[-1]
    if suffix in SI_EXPONENTS:
        value = float(f"{text[:-1]}e{SI_EXPONENTS[suffix]}")
    elif any(c in text for c in ".eE"):
        value = float(text)
    else:
        if len(text.lstrip("0")) > MAX_INTEGER_DIGITS:
            raise LiteralError(f"integer literal with {len(text)} digits is too large: numbers "
                               f"must stay below 1.8e308 (at most {MAX_INTEGER_DIGITS} digits)")
        return int(text)
    if math.isinf(value):
        raise LiteralError(f"number `{_shorten(text)}` is too large: it overflows a 64-bit float "
                           "(largest 1.8e308)")
    return value


def _shorten(text: str) -> str:
    return text if len(text) <= 24 else f"{text[:10]}...{text[-6:]}"


def canonical(obj: dict) -> str:
    return json.dumps(obj, sort_keys=True)


@dataclass(frozen=True)
class Doc:
    text: str


@dataclass(frozen=True)
class Suffix:
    kind: str           # 'metadata' | 'link' | 'condition'
    value: object
    span: Span | None


@dataclass(frozen=True)
class Binding:
    initial: bool
    value: ast.Expr


@dataclass(frozen=True)
class TypeCall:
    name: str
    modifications: tuple


@dataclass(frozen=True)
class TypePart:
    kind: str           # 'dims' | 'modifications'
    value: tuple
    span: Span | None


@dataclass(frozen=True)
class Body:
    extends: tuple
    declarations: tuple
    relations: tuple
    metadata: str | None


@dataclass(frozen=True)
class RelationsSection:
    relations: tuple


@dataclass(frozen=True)
class Metadata:
    text: str


@dataclass(frozen=True)
class Else:
    body: tuple
    closed: bool = False        # a switch's `else` closed by its own `end` (Dyad's form)


@dataclass(frozen=True)
class CallArgs:
    args: tuple
    kwargs: tuple


@dataclass(frozen=True)
class Suffixes:
    metadata: str | None
    link: str | None
    condition: ast.Expr | None
    condition_span: Span | None


def split_doc(children: list) -> tuple[str | None, list]:
    if children and isinstance(children[0], Doc):
        return children[0].text, children[1:]
    return None, children


def split_suffixes(children: list, what: str) -> tuple[Suffixes, list]:
    """The metadata, `{^link}` and `if` condition after a declaration or relation, and the rest."""
    found: dict[str, Suffix] = {}
    rest = []
    for child in children:
        if not isinstance(child, Suffix):
            rest.append(child)
            continue
        if child.kind in found:
            words = {"metadata": "two metadata objects", "link": "two `{^...}` links",
                     "condition": "two `if` conditions"}[child.kind]
            raise DyadError(f"{what} has {words}", child.span)
        found[child.kind] = child
    condition = found.get("condition")
    return Suffixes(found["metadata"].value if "metadata" in found else None,
                    found["link"].value if "link" in found else None,
                    condition.value if condition else None,
                    condition.span if condition else None), rest


class RuleBase:
    """Spans and errors for the rule mixins; `filename` is set by the builder."""
    filename: str

    def _span(self, meta) -> Span | None:
        return meta_span(meta, self.filename)

    def _tspan(self, tok: Token) -> Span:
        return token_span(tok, self.filename)

    def _error(self, message: str, span: Span | None, hint: str | None = None) -> DyadError:
        return DyadError(message, span, hint)
