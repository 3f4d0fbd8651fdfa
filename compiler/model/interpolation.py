"""Interpolation of tabulated data as a function of one real argument, usable in equations.

Dyad libraries build interpolators with DataInterpolations.jl (`LinearInterpolation(u, t)`, ...)
from a dataset (compiler/model/datasets.py). dyadc builds the same functions itself, each as a
piecewise polynomial: pieces that are polynomials in (x - origin), switched at breakpoints.

- `LinearInterpolation`: the chord between neighbouring samples.
- `ConstantInterpolation`: zero-order hold, the value of the last sample at or before x.
- `QuadraticInterpolation`: on [t_i, t_i+1) the parabola through samples i, i+1, i+2 (the last
  interval reuses the parabola of the one before it): DataInterpolations' default, forward form.
- `CubicSpline`: the natural cubic spline (second derivative zero at both ends).

Outside the samples the first and last pieces continue (DataInterpolations' `Extension`; Dyad's
own default refuses such arguments with an error, which a solver stepping past the last sample
would hit), or, as an `extrapolation_type` asks, hold the end values, follow the end tangents,
repeat the table (`Periodic`) or mirror it at every multiple of its span (`Reflective`). A
repeating table (`Wrap`) is applied to two arguments in sympy, f(x, x): the second only picks the
period, so that compiler/lower/events.py can read it from the event clock between time events.
The derivative of a piecewise polynomial is one again, so the derivatives that IDAS's Jacobians need
are exact wherever the interpolant is smooth, and zero for the hold.

In sympy the function is an `InterpolatedFunction` applied to its argument; the CasADi lowering
evaluates it with `select(condition, a, b)` (an if-else chain over the breakpoints, plain
arithmetic otherwise), so the VM, generated C and generated Python modules all run it. The cost of
one evaluation grows linearly with the number of samples.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, Callable

import sympy
from sympy.core.function import ArgumentIndexError


@dataclass(frozen=True)
class Wrap:
    """How a table repeats outside [first, first + period]: `Periodic` shifts by whole periods,
    `Reflective` mirrors it at every first + k * period; `odd` (the derivative of a reflective
    table) also flips the sign on the mirrored periods."""
    first: float
    period: float
    reflective: bool
    odd: bool = False

    def position(self, x: Any, clock: Any, floor: Callable[[Any], Any],
                 select: Callable[[Any, Any, Any], Any]) -> tuple[Any, Any]:
        """(where in [first, first + period] to read the table, the sign to apply) for argument
        `x`, in the period that `clock` (x itself, or x read on the event clock) lies in."""
        k = floor((clock - self.first) / self.period)
        offset = x - self.first - k * self.period
        if not self.reflective:
            return self.first + offset, 1.0
        mirrored = k - 2 * floor(k / 2) > 0.5                 # an odd period
        position = select(mirrored, self.first + self.period - offset, self.first + offset)
        return position, (select(mirrored, -1.0, 1.0) if self.odd else 1.0)

    def differentiated(self) -> "Wrap":
        return dataclasses.replace(self, odd=not self.odd) if self.reflective else self


def _python_select(condition: Any, a: Any, b: Any) -> Any:
    return a if condition else b


@dataclass(frozen=True)
class PiecewisePolynomial:
    """Piece k holds on [breaks[k-1], breaks[k]); the first piece also left of breaks[0], the last
    also right of breaks[-1]. A piece is (origin, coefficients of 1, d, d^2, ... with d = x - origin).
    With a `wrap` the pieces are read at the argument brought into the first period."""
    breaks: tuple[float, ...]
    pieces: tuple[tuple[float, tuple[float, ...]], ...]
    label: str                               # what it interpolates, for messages and printing
    wrap: Wrap | None = None

    def piece_index(self, x: float) -> int:
        from bisect import bisect_right
        return bisect_right(self.breaks, x)

    def value(self, x: float, clock: float | None = None) -> float:
        sign = 1.0
        if self.wrap is not None:
            x, sign = self.wrap.position(x, x if clock is None else clock, math.floor,
                                         _python_select)
        origin, coefficients = self.pieces[self.piece_index(x)]
        return sign * _horner(coefficients, x - origin)

    def derivative(self) -> "PiecewisePolynomial | None":
        """The derivative, None where it is zero everywhere (a hold)."""
        pieces = tuple((origin, tuple(k * c for k, c in enumerate(coefficients) if k) or (0.0,))
                       for origin, coefficients in self.pieces)
        if all(all(c == 0 for c in coefficients) for _, coefficients in pieces):
            return None
        wrap = self.wrap.differentiated() if self.wrap is not None else None
        return PiecewisePolynomial(self.breaks, pieces, f"d/dx {self.label}", wrap)

    def evaluate(self, x: Any, select: Callable[[Any, Any, Any], Any],
                 floor: Callable[[Any], Any] = math.floor, clock: Any = None) -> Any:
        """The value at a symbolic or numeric `x`: `select(x < b, below, above)` switches pieces;
        a wrapped table picks its period with `floor` of `clock` (default: `x`)."""
        sign = 1.0
        if self.wrap is not None:
            x, sign = self.wrap.position(x, x if clock is None else clock, floor, select)
        result = _horner(self.pieces[-1][1], x - self.pieces[-1][0])
        for k in range(len(self.breaks) - 1, -1, -1):
            origin, coefficients = self.pieces[k]
            result = select(x < self.breaks[k], _horner(coefficients, x - origin), result)
        return result if self.wrap is None else sign * result


def _horner(coefficients: tuple[float, ...], d: Any) -> Any:
    result = coefficients[-1]
    for c in reversed(coefficients[:-1]):
        result = result * d + c
    return result


# ------------------------------------------------------------------------------- the kinds

class InterpolationError(ValueError):
    """Data an interpolation cannot be built from; the caller locates it."""


def _checked(u: list[float], t: list[float], least: int, kind: str) -> None:
    if len(u) != len(t):
        raise InterpolationError(f"{kind} needs as many values as times, got {len(u)} and {len(t)}")
    if len(t) < least:
        raise InterpolationError(f"{kind} needs at least {least} samples, got {len(t)}")
    for k in range(1, len(t)):
        if not t[k] > t[k - 1]:
            raise InterpolationError(f"{kind} needs strictly increasing times, but sample {k + 1} "
                                     f"({t[k]!r}) does not follow sample {k} ({t[k - 1]!r})")


def linear(u: list[float], t: list[float], label: str) -> PiecewisePolynomial:
    _checked(u, t, 2, "LinearInterpolation")
    pieces = tuple((t[i], (u[i], (u[i + 1] - u[i]) / (t[i + 1] - t[i]))) for i in range(len(t) - 1))
    return PiecewisePolynomial(tuple(t[1:-1]), pieces, label)


def constant(u: list[float], t: list[float], label: str) -> PiecewisePolynomial:
    _checked(u, t, 1, "ConstantInterpolation")
    return PiecewisePolynomial(tuple(t[1:]), tuple((t[i], (u[i],)) for i in range(len(t))), label)


def quadratic(u: list[float], t: list[float], label: str) -> PiecewisePolynomial:
    _checked(u, t, 3, "QuadraticInterpolation")
    pieces = []
    for i in range(len(t) - 2):
        # Newton's form through samples i, i+1, i+2, rewritten in powers of d = x - t[i]
        h = t[i + 1] - t[i]
        first = (u[i + 1] - u[i]) / h
        second = ((u[i + 2] - u[i + 1]) / (t[i + 2] - t[i + 1]) - first) / (t[i + 2] - t[i])
        pieces.append((t[i], (u[i], first - second * h, second)))
    return PiecewisePolynomial(tuple(t[1:-2]), tuple(pieces), label)


def cubic_spline(u: list[float], t: list[float], label: str) -> PiecewisePolynomial:
    _checked(u, t, 2, "CubicSpline")
    n = len(t)
    h = [t[i + 1] - t[i] for i in range(n - 1)]
    # second derivatives m: natural ends m[0] = m[n-1] = 0, a tridiagonal system inside (Thomas)
    m = [0.0] * n
    if n > 2:
        diagonal = [2 * (h[i - 1] + h[i]) for i in range(1, n - 1)]
        right = [6 * ((u[i + 1] - u[i]) / h[i] - (u[i] - u[i - 1]) / h[i - 1]) for i in range(1, n - 1)]
        for k in range(1, n - 2):
            factor = h[k] / diagonal[k - 1]
            diagonal[k] -= factor * h[k]
            right[k] -= factor * right[k - 1]
        inner = [0.0] * (n - 2)
        inner[-1] = right[-1] / diagonal[-1]
        for k in range(n - 4, -1, -1):
            inner[k] = (right[k] - h[k + 1] * inner[k + 1]) / diagonal[k]
        m[1:n - 1] = inner
    pieces = tuple((t[i], (u[i], (u[i + 1] - u[i]) / h[i] - h[i] * (2 * m[i] + m[i + 1]) / 6,
                           m[i] / 2, (m[i + 1] - m[i]) / (6 * h[i]))) for i in range(n - 1))
    return PiecewisePolynomial(tuple(t[1:-1]), pieces, label)


KINDS: dict[str, Callable[[list[float], list[float], str], PiecewisePolynomial]] = {
    "LinearInterpolation": linear,
    "ConstantInterpolation": constant,
    "QuadraticInterpolation": quadratic,
    "CubicSpline": cubic_spline,
}


# Dyad's `BlockComponents.Tables.ExtrapolationType` members that dyadc builds: how the interpolant
# continues left of the first sample and right of the last. `None` (Dyad: an error outside the
# samples) continues the end pieces as `Extension` does.
EXTRAPOLATIONS = ("None", "Constant", "Linear", "Extension", "Periodic", "Reflective")


def extrapolated(table: PiecewisePolynomial, first: float, last: float,
                 how: str) -> PiecewisePolynomial:
    """`table` (built on samples from `first` to `last`) continued outside them `how`: `Constant`
    holds the end values, `Linear` follows the end tangents, `Extension` and `None` continue the
    end pieces (the table as it is), `Periodic` repeats it with period T = last - first
    (A(x + T) = A(x)), `Reflective` mirrors it at first + k T (A(c + d) = A(c - d) there)."""
    if how in ("Extension", "None"):
        return table
    if how in ("Periodic", "Reflective"):
        if not last > first:
            raise InterpolationError(f"{how} extrapolation needs samples spanning an interval, "
                                     f"got one at {first!r}")
        return dataclasses.replace(table, wrap=Wrap(first, last - first, how == "Reflective"),
                                   label=f"{table.label}, {how} outside")
    derivative = table.derivative() if how == "Linear" else None

    def end_piece(x: float) -> tuple[float, tuple[float, ...]]:
        slope = derivative.value(x) if derivative is not None else 0.0
        return x, (table.value(x), slope) if how == "Linear" else (table.value(x),)

    breaks, pieces = list(table.breaks), list(table.pieces)
    if not breaks or first < breaks[0]:
        breaks.insert(0, first)
        pieces.insert(0, end_piece(first))
    if last > breaks[-1]:               # a hold's last piece already starts at the last sample
        breaks.append(last)
        pieces.append(end_piece(last))
    return PiecewisePolynomial(tuple(breaks), tuple(pieces), f"{table.label}, {how} outside")


@dataclass(frozen=True)
class InterpolationKind:
    """The value of a name such as `LinearInterpolation`: which interpolation to build."""
    name: str

    def build(self, u: list[float], t: list[float], label: str) -> PiecewisePolynomial:
        return KINDS[self.name](u, t, label)


# ----------------------------------------------------------------------------- in sympy

class InterpolatedFunction(sympy.Function):
    """Base of the applied interpolants; each subclass carries its `table` (made by `function`).
    A wrapped table takes (x, clock): the value at x in the period that clock lies in."""
    nargs = (1, 2)
    table: PiecewisePolynomial

    @classmethod
    def eval(cls, x, clock=None):
        arguments = (x,) if clock is None else (x, clock)
        if all(a.is_Number and a.is_finite for a in arguments):
            return sympy.Float(cls.table.value(*(float(a) for a in arguments)))
        return None

    def fdiff(self, argindex: int = 1):
        if argindex == 2:
            return sympy.S.Zero                  # the period is piecewise constant in the clock
        if argindex != 1:
            raise ArgumentIndexError(self, argindex)
        derivative = self.table.derivative()
        return sympy.S.Zero if derivative is None else function(derivative, f"{type(self).__name__}'")(
            *self.args)

    def _eval_is_real(self):
        return self.args[0].is_real


def applied_to(table: PiecewisePolynomial, name: str, argument: Any) -> Any:
    """`table` named `name` applied to `argument` in an equation (a wrapped one as f(x, x))."""
    cls = function(table, name)
    return cls(argument) if table.wrap is None else cls(argument, argument)


_CLASSES: dict[tuple[str, PiecewisePolynomial], type] = {}


def function(table: PiecewisePolynomial, name: str) -> type:
    """The sympy function class of `table`, named `name` in printed equations; one class per
    (name, table), so that equal interpolants give equal expressions."""
    key = (name, table)
    found = _CLASSES.get(key)
    if found is None:
        found = _CLASSES[key] = type(InterpolatedFunction)(name, (InterpolatedFunction,),
                                                          {"table": table})
    return found
