"""Typed AST of the Dyad-like language.

Every node carries its source `span`; spans are excluded from equality so that
`parse(fmt(x)) == parse(x)` compares structure only. Sequences are tuples so nodes stay immutable.
Metadata JSON is kept as a canonical JSON string (`json.dumps(obj, sort_keys=True)`) to stay hashable;
use `metadata_dict()` to read it.
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Union

from compiler.errors import Span

_NO_SPAN = field(default=None, compare=False, repr=False)


def metadata_dict(metadata: str | None) -> dict:
    return json.loads(metadata) if metadata else {}


# ----------------------------------------------------------------------------------- expressions

@dataclass(frozen=True)
class Number:
    value: float | int          # SI suffixes already applied: `10k` -> 10000.0
    span: Span | None = _NO_SPAN
    # The literal as written (`3e4`, `10k`); only for faithful reprinting, not compared.
    text: str | None = field(default=None, compare=False, repr=False)


@dataclass(frozen=True)
class String:
    value: str
    span: Span | None = _NO_SPAN


@dataclass(frozen=True)
class Boolean:
    value: bool
    span: Span | None = _NO_SPAN


@dataclass(frozen=True)
class End:
    """`end` inside an index: the last element of the indexed dimension."""
    span: Span | None = _NO_SPAN


@dataclass(frozen=True)
class Colon:
    """A bare `:` index: the whole dimension."""
    span: Span | None = _NO_SPAN


@dataclass(frozen=True)
class RefPart:
    name: str
    indices: tuple["Expr", ...] = ()


@dataclass(frozen=True)
class Ref:
    """A (possibly qualified, possibly indexed) name: `frame_a.x`, `v[1]`, `links[i].frame_b.phi`."""
    parts: tuple[RefPart, ...]
    span: Span | None = _NO_SPAN

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
    span: Span | None = _NO_SPAN


@dataclass(frozen=True)
class UnaryOp:
    op: str                      # '-', '+', '!' (also 'not')
    operand: "Expr"
    span: Span | None = _NO_SPAN


@dataclass(frozen=True, eq=False, repr=False)
class BinaryOp:
    # '+', '-', '*', '/', '^', '.+', '.-', '.*', './', '.^', '%', '÷',
    # '<', '<=', '>', '>=', '==', '!=', 'and', 'or'
    op: str
    left: "Expr"
    right: "Expr"
    span: Span | None = _NO_SPAN

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
    span: Span | None = _NO_SPAN


@dataclass(frozen=True)
class KeywordArg:
    name: str
    value: "Expr"
    span: Span | None = _NO_SPAN


@dataclass(frozen=True)
class Call:
    """`f(a, b; k = v)` or `f(a, k = v)`; `function` is the (qualified) name, e.g. `der`, `sin`,
    `MultibodyComponents.PlanarMechanics.gravity_acceleration_2d`."""
    function: str
    args: tuple["Expr", ...] = ()
    kwargs: tuple[KeywordArg, ...] = ()
    span: Span | None = _NO_SPAN


@dataclass(frozen=True)
class ArrayLit:
    """`[a, b, c]`; a matrix literal `[a b; c d]` is an ArrayLit of row ArrayLits with `is_matrix`."""
    elements: tuple["Expr", ...]
    is_matrix: bool = False
    span: Span | None = _NO_SPAN


@dataclass(frozen=True)
class Iterator:
    variable: str
    iterable: "Expr"
    span: Span | None = _NO_SPAN


@dataclass(frozen=True)
class Comprehension:
    """`[expr for i in 1:n]` (several iterators allowed)."""
    expr: "Expr"
    iterators: tuple[Iterator, ...]
    span: Span | None = _NO_SPAN


Expr = Union[Number, String, Boolean, End, Colon, Ref, Range, UnaryOp, BinaryOp, IfExpr, Call,
             ArrayLit, Comprehension]


# ---------------------------------------------------------------------------------- declarations

@dataclass(frozen=True)
class Modification:
    """One modifier: `m = 2`, `phi(initial = 0.3)`, `final k = 1`, `x(guess = 1) = 2`.

    `name` may be dotted (`body.m = 2`). `value` is None when only nested modifiers are given.
    """
    name: str
    value: "Expr | None" = None
    nested: tuple["Modification", ...] = ()
    final: bool = False
    span: Span | None = _NO_SPAN


@dataclass(frozen=True)
class TypeSpec:
    """`Real`, `Length`, `Real(units = "m", guess = 1)`, `Real[2]`, `Real[n, 3]`."""
    name: str                                   # possibly qualified: `Pkg.Length`
    modifications: tuple[Modification, ...] = ()
    dims: tuple["Expr", ...] = ()
    span: Span | None = _NO_SPAN


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
    span: Span | None = _NO_SPAN
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
    span: Span | None = _NO_SPAN
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
    span: Span | None = _NO_SPAN
    link: str | None = None


@dataclass(frozen=True)
class Extends:
    type_name: str
    modifications: tuple[Modification, ...] = ()
    metadata: str | None = None
    span: Span | None = _NO_SPAN
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
    span: Span | None = _NO_SPAN
    link: str | None = None


Declaration = Union[ParameterDecl, VariableDecl, ComponentDecl, TypedDecl]


# ------------------------------------------------------------------------------------- relations

@dataclass(frozen=True)
class Equation:
    lhs: "Expr"
    rhs: "Expr"
    initial: bool = False
    doc: str | None = None
    span: Span | None = _NO_SPAN
    metadata: str | None = None
    link: str | None = None


@dataclass(frozen=True)
class Guess:
    target: Ref
    value: "Expr"
    span: Span | None = _NO_SPAN
    doc: str | None = None


@dataclass(frozen=True)
class Connect:
    """`connect(a, b, ...)`; `u: analysis_point(a, b)` is the same connection, named `u` for
    linear analyses (`analysis_point` holds the name)."""
    refs: tuple[Ref, ...]
    doc: str | None = None
    span: Span | None = _NO_SPAN
    metadata: str | None = None           # diagram routing JSON after `connect(...)`
    link: str | None = None
    analysis_point: str | None = None


@dataclass(frozen=True)
class Continuity:
    """`continuity(a.medium, b.medium)`: the media are one; recorded, implies no equation."""
    refs: tuple["Expr", ...]
    doc: str | None = None
    span: Span | None = _NO_SPAN
    metadata: str | None = None
    link: str | None = None


@dataclass(frozen=True)
class ForLoop:
    iterators: tuple[Iterator, ...]
    body: tuple["Relation", ...]
    span: Span | None = _NO_SPAN
    doc: str | None = None


@dataclass(frozen=True)
class IfBranch:
    condition: "Expr"
    body: tuple["Relation", ...]
    span: Span | None = _NO_SPAN


@dataclass(frozen=True)
class IfRelation:
    branches: tuple[IfBranch, ...]              # `if` then each `elseif`
    otherwise: tuple["Relation", ...] = ()
    span: Span | None = _NO_SPAN
    doc: str | None = None


@dataclass(frozen=True)
class SwitchCase:
    names: tuple[str, ...]                      # `case A, B`: the enum members (maybe qualified)
    body: tuple["Relation", ...]
    span: Span | None = _NO_SPAN


@dataclass(frozen=True)
class Switch:
    """`switch subject case A ... case B ... else ... end` on a structural (enum) parameter."""
    subject: "Expr"
    cases: tuple[SwitchCase, ...]
    otherwise: tuple["Relation", ...] = ()
    span: Span | None = _NO_SPAN
    doc: str | None = None


Relation = Union[Equation, Guess, Connect, Continuity, ForLoop, IfRelation, Switch]


# ----------------------------------------------------------------------------------- definitions

@dataclass(frozen=True)
class ConnectorField:
    name: str
    kind: str                                   # 'potential' | 'flow' | 'input' | 'output' | 'stream' | 'path'
    type: TypeSpec
    doc: str | None = None
    metadata: str | None = None
    span: Span | None = _NO_SPAN
    link: str | None = None


@dataclass(frozen=True)
class ConnectorDef:
    name: str
    fields: tuple[ConnectorField, ...]
    partial: bool = False
    doc: str | None = None
    metadata: str | None = None
    span: Span | None = _NO_SPAN


@dataclass(frozen=True)
class SignalConnectorDef:
    """`connector RealInput = input Real` (optionally with type modifiers / dims)."""
    name: str
    causality: str                              # 'input' | 'output'
    type: TypeSpec
    doc: str | None = None
    metadata: str | None = None
    span: Span | None = _NO_SPAN
    link: str | None = None


@dataclass(frozen=True)
class TypeDef:
    """`type Length = Real(units = "m")`."""
    name: str
    base: TypeSpec
    doc: str | None = None
    span: Span | None = _NO_SPAN


@dataclass(frozen=True)
class EnumDef:
    name: str
    members: tuple[str, ...]
    doc: str | None = None
    span: Span | None = _NO_SPAN
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
    span: Span | None = _NO_SPAN


@dataclass(frozen=True)
class StructDef:
    """`struct Name  field::Type = default ... end`: a record of named values."""
    name: str
    fields: tuple[TypedDecl, ...]
    doc: str | None = None
    span: Span | None = _NO_SPAN


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
    span: Span | None = _NO_SPAN
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
    span: Span | None = _NO_SPAN


@dataclass(frozen=True)
class Using:
    """`using Package: a, b` or `using Package`."""
    package: str
    names: tuple[str, ...] = ()
    span: Span | None = _NO_SPAN


Definition = Union[ComponentDef, ConnectorDef, SignalConnectorDef, TypeDef, EnumDef, AnalysisDef,
                   FunctionTypeDef, StructDef]


@dataclass(frozen=True)
class File:
    path: str = field(compare=False)
    usings: tuple[Using, ...] = ()
    definitions: tuple[Definition, ...] = ()
    span: Span | None = _NO_SPAN
