"""Units with unknowns, and the constraints among them.

A `Dim` is a known Unit times powers of inference variables: the unit of a bare literal or of a
declaration typed `::Real` is not written, so each such declaration instance gets a variable
(one per instance: a Gain carries volts in one place and amperes in another). Every equation,
binding and connect adds constraints `left == right`; `solve` propagates: a constraint with one
unknown left fixes it, one with none left is checked (dimension, then conversion factor 1).
A constraint among unknowns that nothing fixes checks nothing (no unit to compare), and a
mismatch counts only when a declared unit takes part in it, directly or through the variables it
fixed: a model written without units (`der(x) = v + log(x)`, every name `::Real`) states none to
check, as OpenModelica reports only inconsistencies "due to specified unit information".
"""
from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from compiler.errors import Span
from compiler.units.quantity import ONE, Unit


class Dim:
    """`unit` times the product of variable ** exponent over `powers` (sorted (var, exponent)
    pairs, empty when the unit is known); `label` is the unit as declared, for messages;
    `declared`: some declaration's unit is part of it (not only time's second or a function's 1)."""
    __slots__ = ("unit", "powers", "label", "declared")

    def __init__(self, unit: Unit, powers: tuple = (), label: str | None = None,
                 declared: bool = False):
        self.unit = unit
        self.powers = powers
        self.label = label
        self.declared = declared

    def __mul__(self, other: "Dim") -> "Dim":
        powers = _merge(self.powers, other.powers, 1) if other.powers else self.powers
        return Dim(self.unit * other.unit, powers, None, self.declared or other.declared)

    def __truediv__(self, other: "Dim") -> "Dim":
        powers = _merge(self.powers, other.powers, -1) if other.powers else self.powers
        return Dim(self.unit / other.unit, powers, None, self.declared or other.declared)

    def __pow__(self, power: int | Fraction) -> "Dim":
        powers = tuple((v, _exact(e * power)) for v, e in self.powers) if self.powers else ()
        return Dim(self.unit ** power, powers, None, self.declared)


def _exact(value):
    if isinstance(value, Fraction) and value.denominator == 1:
        return int(value)
    return value


def _merge(left: tuple, right: tuple, sign: int) -> tuple:
    merged = dict(left)
    for var, exponent in right:
        total = merged.get(var, 0) + sign * exponent
        if total:
            merged[var] = total
        else:
            merged.pop(var, None)
    return tuple(sorted(merged.items()))


DIMENSIONLESS = Dim(ONE)


class Free:
    """The unit of a bare literal (and of sums of them): whatever its context demands; as a
    factor of a product, a pure number."""
    __slots__ = ()

    def __repr__(self) -> str:
        return "FREE"


FREE = Free()
# None stands for "not known" (a Julia function's result, a name the check cannot follow): it
# constrains nothing.


@dataclass
class Site:
    """Where a constraint comes from: its kind (equation, binding, connection, sum, argument,
    branch, comparison, array, value), the term to underline (`span`), the term it is compared
    with (`other`), the two labels a message names them by and the instance path that uses it."""
    kind: str
    span: Span | None
    other: Span | None
    labels: tuple[str, str]
    path: str
    instance: Span | None               # where that instance is declared
    statement: Span | None = None
    declared: Span | None = None        # a binding: where the bound name is declared


@dataclass
class Mismatch:
    site: Site
    left: Unit
    right: Unit
    factor: float | None                # compatible units: how many `right` in one `left`
    inferred: list[tuple[str, Span | None]] = field(default_factory=list)
    labels: tuple[str | None, str | None] = (None, None)    # the units as declared, if declared


class Solver:
    """The inference variables, their units once fixed, and the pending constraints."""

    def __init__(self) -> None:
        self.values: list[Unit | None] = []
        self.names: list[str] = []
        self.fixed_at: list[Span | None] = []
        self.grounded: list[bool] = []          # fixed from a declared unit, directly or not
        self.constraints: list[tuple[Dim, Dim, Site]] = []

    def variable(self, name: str) -> Dim:
        self.values.append(None)
        self.names.append(name)
        self.fixed_at.append(None)
        self.grounded.append(False)
        return Dim(ONE, ((len(self.values) - 1, 1),))

    def require(self, left: Any, right: Any, site: Site) -> None:
        """`left` and `right` (Dims, FREE or None) must be one unit."""
        if type(left) is Dim and type(right) is Dim:
            self.constraints.append((left, right, site))

    def solve(self) -> list[Mismatch]:
        mismatched: list[tuple[Dim, Dim, Site]] = []
        waiting: dict[int, list[int]] = {}
        queue = deque(range(len(self.constraints)))       # source order, then as unknowns are fixed
        done = [False] * len(self.constraints)
        while queue:
            index = queue.popleft()
            if done[index]:
                continue
            left, right, site = self.constraints[index]
            unit, unknown = self._residual(left, right)
            if len(unknown) > 1:
                for var in unknown:
                    waiting.setdefault(var, []).append(index)
                continue
            done[index] = True
            if unknown:
                (var, exponent), = unknown.items()
                self.values[var] = ONE / unit if exponent == 1 else unit if exponent == -1 \
                    else unit ** _exact(Fraction(-1) / exponent)
                self.fixed_at[var] = site.span
                self.grounded[var] = self._declared(left, right)
                queue.extend(waiting.pop(var, []))
            elif not unit.consistent_with(ONE):
                mismatched.append((left, right, site))
        # whether a declared unit takes part is known once every variable that can be is fixed
        found = [self._mismatch(*m) for m in mismatched if self._declared(m[0], m[1])]
        found.sort(key=lambda m: _order(m.site.span))
        return found

    def _declared(self, left: Dim, right: Dim) -> bool:
        return left.declared or right.declared or any(
            self.grounded[var] for var, _ in left.powers + right.powers)

    def _residual(self, left: Dim, right: Dim) -> tuple[Unit, dict[int, Any]]:
        """left / right with the fixed variables substituted, and the exponents still unknown."""
        unit = left.unit / right.unit
        unknown: dict[int, Any] = {}
        for powers, sign in ((left.powers, 1), (right.powers, -1)):
            for var, exponent in powers:
                value = self.values[var]
                if value is None:
                    total = unknown.get(var, 0) + sign * exponent
                    if total:
                        unknown[var] = total
                    else:
                        unknown.pop(var, None)
                elif exponent == 1:
                    unit = unit * value if sign == 1 else unit / value
                else:
                    unit = unit * value ** (sign * exponent)
        return unit, unknown

    def unit_of(self, dim: Dim) -> Unit:
        """`dim` with every fixed variable substituted (unfixed ones read as 1)."""
        unit = dim.unit
        for var, exponent in dim.powers:
            value = self.values[var]
            if value is not None:
                unit = unit * value ** exponent
        return unit

    def _mismatch(self, left: Dim, right: Dim, site: Site) -> Mismatch:
        a, b = self.unit_of(left), self.unit_of(right)
        factor = a.factor / b.factor if a.exponents == b.exponents else None
        inferred = [(self.names[v], self.fixed_at[v]) for v, _ in left.powers + right.powers]
        return Mismatch(site, a, b, factor, inferred, (left.label, right.label))


def _order(span: Span | None) -> tuple:
    return (span.file, span.line, span.column) if span else ("", 0, 0)
