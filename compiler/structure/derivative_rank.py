"""Numerical rank of the derivative Jacobian: hidden constraints that structure cannot see.

When derivatives appear only in linear combinations (`C1*(der(y1) - der(y2))` in one equation and
its mirror in another), every voltage looks like a state structurally, but the rows of
d(equations)/d(derivatives) are linearly dependent: a combination of the equations contains no
derivative at all. That combination is an algebraic constraint between would-be states. We
replace one equation of each dependent set by the derivative-free combination; Pantelides then
sees the constraint and the state count drops to the true one.

Only equations whose derivative coefficients are constants (numbers and parameters) take part:
for those the dependency holds everywhere, not just at one point.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np
import sympy

from compiler.model.symbols import free_symbols
from compiler.structure.differentiate import partial


@dataclass
class RankReport:
    rows_examined: int = 0
    rank: int = 0
    replaced: list[int] = field(default_factory=list)        # equation indices given a new residual


def remove_derivative_dependencies(equations: list[sympy.Expr], derivative_symbols: set[sympy.Symbol],
                                   parameter_values: dict[sympy.Symbol, float], tol: float = 1e-10
                                   ) -> tuple[list[sympy.Expr], RankReport]:
    report = RankReport()
    rows, coefficient_rows = [], []
    ders = sorted(derivative_symbols, key=lambda s: s.name)
    der_index = {d: j for j, d in enumerate(ders)}
    for i, eq in enumerate(equations):
        present = [d for d in free_symbols(eq) if d in der_index]
        if not present:
            continue
        row: dict[int, float] = {}                      # sparse: derivative column -> coefficient
        for d in present:
            coefficient = partial(eq, d)
            # (not `free_symbols - parameter_values.keys()`: that walks every parameter, per row)
            if any(s not in parameter_values for s in free_symbols(coefficient)):
                break                                   # depends on unknowns (or nonlinear in d)
            value = float(coefficient.xreplace(parameter_values))
            if value != 0.0:
                row[der_index[d]] = value
        else:
            rows.append(i)
            coefficient_rows.append(row)
    report.rows_examined = len(rows)
    if not rows:
        return list(equations), report

    result = list(equations)
    rank = 0
    # Rows can only depend on rows that share a derivative with them (transitively): analyse each
    # connected group on its own; most groups are a single row (linear in the model size).
    for group in _groups_sharing_derivatives(coefficient_rows):
        # dense only over the group's own columns: every other column is zero in all its rows
        columns = sorted({j for k in group for j in coefficient_rows[k]})
        position = {j: c for c, j in enumerate(columns)}
        dense = {}
        for k in group:
            dense[k] = np.zeros(len(columns))
            for j, value in coefficient_rows[k].items():
                dense[k][position[j]] = value
        basis_rows: list[int] = []                      # positions in `rows` that are independent
        for k in group:
            row = dense[k]
            if basis_rows:
                basis = np.array([dense[b] for b in basis_rows])
                weights, *_ = np.linalg.lstsq(basis.T, row, rcond=None)
                residual = row - basis.T @ weights
                scale = max(1.0, float(np.max(np.abs(row))))
                if np.max(np.abs(residual)) <= tol * scale:
                    result[rows[k]] = _combine(result, rows, basis_rows, k, weights, ders)
                    report.replaced.append(rows[k])
                    continue
            basis_rows.append(k)
        rank += len(basis_rows)
    report.rank = rank
    return result, report


def _groups_sharing_derivatives(coefficient_rows: list[dict[int, float]]) -> list[list[int]]:
    """Connected components of rows linked by a common nonzero derivative column (union-find)."""
    parent = list(range(len(coefficient_rows)))

    def find(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    owner: dict[int, int] = {}
    for k, row in enumerate(coefficient_rows):
        for j in sorted(row):
            if j in owner:
                parent[find(k)] = find(owner[j])
            else:
                owner[j] = k
    groups: dict[int, list[int]] = {}
    for k in range(len(coefficient_rows)):
        groups.setdefault(find(k), []).append(k)
    return [sorted(g) for g in groups.values()]


def _combine(equations, rows, basis_rows, k, weights, ders) -> sympy.Expr:
    """equation_k - sum(w_j equation_j): exact rational weights so the derivatives cancel."""
    combined = equations[rows[k]]
    for b, w in zip(basis_rows, weights):
        if abs(w) > 1e-14:
            exact = Fraction(float(w)).limit_denominator(10**6)
            weight = sympy.Rational(exact.numerator, exact.denominator) if abs(float(exact) - w) < 1e-12 * max(1, abs(w)) else sympy.Float(w)
            combined = combined - weight * equations[rows[b]]
    combined = sympy.expand(combined)
    leftover = {d: 0 for d in ders if d in combined.free_symbols}
    return combined.xreplace(leftover) if leftover else combined
