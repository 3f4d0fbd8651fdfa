"""Typed AST of expressions (compiler/syntax/ast.py gathers every node type).

Every node carries its source `span`, excluded from equality (NO_SPAN) so that
`parse(fmt(x)) == parse(x)` compares structure only; sequences are tuples so nodes stay
immutable."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Union

from compiler.errors import Span

NO_SPAN = field(default=None, compare=False, repr=False)


@dataclass(frozen=True)
class Number:
    value: float | int          # SI suffixes already applied: `10k` -> 10000.0
    span: Span | None = NO_SPAN
    # The literal as written (`3e4`, `10k`); only for faithful reprinting, not compared.
    text: str | None = field(default=None, compare=False, repr=False)


@dataclass(frozen=True)
class String:
    value: str
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class Boolean:
    value: bool
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class End:
    """`end` inside an index: the last element of the indexed dimension."""
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class Colon:
    """A bare `:` index: the whole dimension."""
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class RefPart:
    name: str
    indices: tuple["Expr", ...] = ()


@dataclass(frozen=True)
class Ref:
    """A (possibly qualified, possibly indexed) name: `frame_a.x`, `v[1]`, `links[i].frame_b.phi`."""
    parts: tuple[RefPart, ...]
    span: Span | None = NO_SPAN

    @property
    def dotted(self) -> str:
        """The name without indices, e.g. `links.frame_b.phi`."""
        return ".".join(p.name for p in self.parts)


@dataclass(frozen=True)
class Range:
    """`start:stop` or `start:step:stop` (also used for slices)."""
    start: "Expr"
    stop: "Expr"
    step: "Expr | None" = None
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class UnaryOp:
    op: str                      # '-', '+', '!' (also 'not')
    operand: "Expr"
    span: Span | None = NO_SPAN


@dataclass(frozen=True, eq=False, repr=False)
class BinaryOp:
    # '+', '-', '*', '/', '^', '.+', '.-', '.*', './', '.^', '%', '÷',
    # '<', '<=', '>', '>=', '==', '!=', 'and', 'or'
    op: str
    left: "Expr"
    right: "Expr"
    span: Span | None = NO_SPAN

    # A 20000-term sum is a 20000-deep chain of left operands: equality, hashing and repr walk
    # that chain in a loop, recursing only into right operands (whose depth the parser bounds).
    def __eq__(self, other):
        a, b = self, other
        while isinstance(a, BinaryOp) and isinstance(b, BinaryOp):
            if a.op != b.op or a.right != b.right:
                return False
            a, b = a.left, b.left
        if isinstance(a, BinaryOp) or isinstance(b, BinaryOp):
            return False
        return a == b

    def __hash__(self):
        value, node = 0, self
        while isinstance(node, BinaryOp):
            value = hash((value, node.op, node.right))
            node = node.left
        return hash((value, node))

    def __repr__(self):
        chain, node = [], self
        while isinstance(node, BinaryOp):
            chain.append(node)
            node = node.left
        heads = "".join(f"BinaryOp(op={link.op!r}, left=" for link in chain)
        tails = "".join(f", right={link.right!r})" for link in reversed(chain))
        return heads + repr(node) + tails


def left_chain(expr: "BinaryOp", ops) -> tuple["Expr", list["BinaryOp"]]:
    """The leftmost operand and the links of a left-associated chain of operators in `ops`,
    innermost first: `a - b + c` -> (a, [(a - b), (a - b + c)])."""
    links = []
    node = expr
    while isinstance(node, BinaryOp) and node.op in ops:
        links.append(node)
        node = node.left
    links.reverse()
    return node, links


@dataclass(frozen=True)
class IfExpr:
    """`if c then a elseif c2 then b else d` as nested IfExpr; `ifelse(c, a, b)` stays a Call."""
    condition: "Expr"
    then: "Expr"
    otherwise: "Expr"
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class KeywordArg:
    name: str
    value: "Expr"
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class Call:
    """`f(a, b; k = v)` or `f(a, k = v)`; `function` is the (qualified) name, e.g. `der`, `sin`,
    `MultibodyComponents.PlanarMechanics.gravity_acceleration_2d`."""
    function: str
    args: tuple["Expr", ...] = ()
    kwargs: tuple[KeywordArg, ...] = ()
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class ArrayLit:
    """`[a, b, c]`; a matrix literal `[a b; c d]` is an ArrayLit of row ArrayLits with `is_matrix`."""
    elements: tuple["Expr", ...]
    is_matrix: bool = False
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class Iterator:
    variable: str
    iterable: "Expr"
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class ForClause:
    """One `for i in r, j in s [if cond]` of a comprehension after its first."""
    iterators: tuple[Iterator, ...]
    condition: "Expr | None" = None
    span: Span | None = NO_SPAN


@dataclass(frozen=True)
class Comprehension:
    """`[expr for i in 1:n]` (several iterators allowed), as in Julia also filtered
    `[expr for i in 1:n if cond]` (`condition`) and nested `[expr for i in 1:n for j in 1:i]`
    (`more`: the clauses after the first, each inside the one before).

    Without filter and nesting, `for i in r, j in s` is an array of shape (len r, len s); with
    either, the elements that pass form one vector, the last clause varying fastest (Julia).
    `generator` marks Julia's bracketless form, the sole argument of a call: `sum(x[i] for i in 1:n)`
    means `sum([x[i] for i in 1:n])`; the flag only lets `dyadc fmt` print it as written."""
    expr: "Expr"
    iterators: tuple[Iterator, ...]
    span: Span | None = NO_SPAN
    generator: bool = False
    condition: "Expr | None" = None
    more: tuple[ForClause, ...] = ()

    @property
    def clauses(self) -> tuple[ForClause, ...]:
        return (ForClause(self.iterators, self.condition, self.span),) + self.more

    @property
    def is_vector(self) -> bool:
        """A filter or a nested `for` makes the result one vector."""
        return self.condition is not None or bool(self.more)


Expr = Union[Number, String, Boolean, End, Colon, Ref, Range, UnaryOp, BinaryOp, IfExpr, Call,
             ArrayLit, Comprehension]
