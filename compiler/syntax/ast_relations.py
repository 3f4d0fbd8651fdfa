"""Typed AST of relations: equations, guesses, connections, and structural for/if/switch."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Union

from compiler.errors import Span
from compiler.syntax.ast_expressions import NO_SPAN, Expr, Iterator, Ref


@dataclass(frozen=True)
class Equation:
    lhs: "Expr"
    rhs: "Expr"
    initial: bool = False
    doc: str | None = None
    span: Span | None = NO_SPAN
    metadata: str | None = None
    link: str | None = None


@dataclass(frozen=True)
class Guess:
    target: Ref
    value: "Expr"
    span: Span | None = NO_SPAN
    doc: str | None = None


@dataclass(frozen=True)
class Connect:
    """`connect(a, b, ...)`; `u: analysis_point(a, b)` is the same connection, named `u` for
    linear analyses (`analysis_point` holds the name)."""
    refs: tuple[Ref, ...]
    doc: str | None = None
    span: Span | None = NO_SPAN
    metadata: str | None = None           # diagram routing JSON after `connect(...)`
    link: str | None = None
    analysis_point: str | None = None


@dataclass(frozen=True)
class Continuity:
    """`continuity(a.medium, b.medium)`: the media are one; recorded, implies no equation."""
    refs: tuple["Expr", ...]
    doc: str | None = None
    span: Span | None = NO_SPAN
    metadata: str | None = None
    link: str | None = None


@dataclass(frozen=True)
class ForLoop:
    iterators: tuple[Iterator, ...]
    body: tuple["Relation", ...]
    span: Span | None = NO_SPAN
    doc: str | None = None


@dataclass(frozen=True)
class IfBranch:
    condition: "Expr"
    body: tuple["Relation", ...]
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class IfRelation:
    branches: tuple[IfBranch, ...]              # `if` then each `elseif`
    otherwise: tuple["Relation", ...] = ()
    span: Span | None = NO_SPAN
    doc: str | None = None


@dataclass(frozen=True)
class SwitchCase:
    names: tuple[str, ...]          # `case A, Gear.B(), C(x0)`: the enum members as written
    body: tuple["Relation", ...]
    span: Span | None = NO_SPAN

    @property
    def members(self) -> tuple[str, ...]:
        """The members named, `Gear.B()` (the member as a value) and `C(x0)` (binding the fields
        of `C`) read as `Gear.B` and `C`."""
        return tuple(name.partition("(")[0] for name in self.names)

    def bound_names(self, member: str) -> tuple[str, ...]:
        """The local names `case C(x0, y)` binds to the fields of member `C`, in field order."""
        for name in self.names:
            if name.partition("(")[0] == member:
                inside = name.partition("(")[2].removesuffix(")")
                return tuple(part.strip() for part in inside.split(",") if part.strip())
        return ()


@dataclass(frozen=True)
class Switch:
    """`switch subject case A ... case B ... else ... end` on a structural (enum) parameter.

    `closed_cases`: the cases (and `else`) were written Dyad's way, each closed by its own `end`;
    the meaning is the same, the flag lets `dyadc fmt` print the form it read."""
    subject: "Expr"
    cases: tuple[SwitchCase, ...]
    otherwise: tuple["Relation", ...] = ()
    span: Span | None = NO_SPAN
    doc: str | None = None
    closed_cases: bool = False


@dataclass(frozen=True)
class SwitchValue:
    """`y = switch gear case Low 1 end case High 2 end end`: the value of the case a structural
    enum selects. Each case is a SwitchCase whose body is its one value expression; `otherwise`
    is the `else` value, () when there is none."""
    subject: "Expr"
    cases: tuple[SwitchCase, ...]
    otherwise: tuple["Expr", ...] = ()
    span: Span | None = NO_SPAN


Relation = Union[Equation, Guess, Connect, Continuity, ForLoop, IfRelation, Switch]
