"""Two-dimensional tables: `dataset_interpolation(kind1, axis1, kind2, axis2, data)`, Dyad's
`BlockComponents.Tables.InterpolatedTable` (data[i, j] is the value at axis1[i], axis2[j]).

Every kind dyadc builds along one axis (linear, hold) is linear in the sampled values, so the
table is a sum of products of one-dimensional interpolants:

    f(u1, u2) = sum_j  w_j(u2) * c_j(u1)

with c_j the kind1 interpolant of column j over axis1 and w_j the kind2 interpolant over axis2 of
the j-th unit vector (for linear interpolation the hat function of axis2[j]). That is the bilinear
(or hold) table exactly, with exact derivatives in both arguments, built from the pieces of
compiler/model/interpolation.py. Outside the axes the end pieces continue, as for one dimension.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sympy

from compiler.errors import DyadError, Span
from compiler.model import interpolation
from compiler.model.interpolation import InterpolationError, PiecewisePolynomial

# Dyad's `BlockComponents.Tables.InterpolationDimension` members, and the kind each one builds;
# a member missing here (`BSplineInterpolationDimension`) is refused where it is used.
DIMENSION_TYPE = "BlockComponents.Tables.InterpolationDimension"
DIMENSION_KINDS = {"LinearInterpolationDimension": "LinearInterpolation",
                   "ConstantInterpolationDimension": "ConstantInterpolation"}


@dataclass(frozen=True)
class Table2D:
    """f(u1, u2) = sum_j weights[j](u2) * columns[j](u1)."""
    columns: tuple[PiecewisePolynomial, ...]
    weights: tuple[PiecewisePolynomial, ...]
    label: str

    def value(self, u1: float, u2: float) -> float:
        return sum(w.value(u2) * c.value(u1) for w, c in zip(self.weights, self.columns))


def build(kind1: str, axis1: list[float], kind2: str, axis2: list[float], data: Any,
          label: str) -> Table2D:
    """The table of `data` (len(axis1) rows, len(axis2) columns); InterpolationError when the
    data do not fit the axes or an axis cannot be interpolated."""
    rows, cols = len(axis1), len(axis2)
    if getattr(data, "shape", None) != (rows, cols):
        raise InterpolationError(f"the data must have one row per point of axis1 and one column "
                                 f"per point of axis2, {rows} x {cols}, got "
                                 f"{' x '.join(str(n) for n in getattr(data, 'shape', ()))}")
    along1, along2 = interpolation.KINDS[kind1], interpolation.KINDS[kind2]
    columns = tuple(along1([float(v) for v in data[:, j]], list(axis1), f"{label}, column {j + 1}")
                    for j in range(cols))
    weights = tuple(along2([1.0 if k == j else 0.0 for k in range(cols)], list(axis2),
                           f"{label}, weight {j + 1}") for j in range(cols))
    return Table2D(columns, weights, label)


def applied(table: Table2D, path: str, arguments: list, span: Span | None) -> Any:
    """`interpolator(u1, u2)` in an equation."""
    if len(arguments) != 2:
        raise DyadError(f"`{path}` is a two-dimensional table: it takes two arguments, got "
                        f"{len(arguments)}", span)
    u1, u2 = arguments
    return sympy.Add(*[interpolation.function(w, f"{path}_w{j + 1}")(u2)
                       * interpolation.function(c, f"{path}_c{j + 1}")(u1)
                       for j, (w, c) in enumerate(zip(table.weights, table.columns))])
