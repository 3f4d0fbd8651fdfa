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

import math
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
    """The equations with one equation of each dependent set replaced by its derivative-free
    combination. A dependency may hide behind an auxiliary variable that names a combination of
    derivatives (`a = der(y4) - der(y5)`, `C3 * a = ...` beside `C3 * (der(y5) - der(y4)) = ...`):
    the analysis is repeated with such auxiliaries replaced by their definitions in the other
    equations (the definitions left out), and its replacements are taken where it finds more
    dependencies than the first analysis found genuine ones (models without hidden ones keep the
    first analysis as it was)."""
    result, report = _remove_dependencies(equations, derivative_symbols, parameter_values, tol)
    definitions = _derivative_definitions(equations, derivative_symbols, parameter_values)
    if not definitions:
        return result, report
    # The definitions themselves stay out of the second analysis: their rows are what the
    # substitution already accounts for (kept in, `w = der(v)` and `m * w = f` would look dependent).
    defining = {i for i, _ in definitions.values()}
    rule = {v: expr for v, (_, expr) in definitions.items()}
    substituted = [sympy.Integer(0) if i in defining else eq.xreplace(rule) for i, eq in enumerate(equations)]
    again, report_again = _remove_dependencies(substituted, derivative_symbols, parameter_values, tol)
    # What the first analysis found may be no constraint between would-be states: a definition
    # found dependent on the equation it hides in, or a combination that still holds an auxiliary
    # (a derivative in disguise). Only the replaced rows change; the others keep their auxiliaries.
    genuine = [i for i in report.replaced if i not in defining and not free_symbols(result[i]) & rule.keys()]
    if len(report_again.replaced) > len(genuine):
        replaced = set(report_again.replaced)
        return [again[i] if i in replaced else eq for i, eq in enumerate(equations)], report_again
    return result, report


def _derivative_definitions(equations, derivative_symbols, parameter_values) -> dict:
    """auxiliary -> (its equation, the combination) for every auxiliary that one equation defines
    as a combination of derivatives with constant coefficients (`v = der(a) - der(b)`; v itself
    never differentiated)."""
    definitions: dict[sympy.Symbol, tuple[int, sympy.Expr]] = {}
    for i, eq in enumerate(equations):
        symbols = free_symbols(eq)
        others = [s for s in symbols if s not in derivative_symbols and s not in parameter_values]
        if len(others) != 1 or not symbols & derivative_symbols or others[0] in definitions \
                or sympy.Symbol(f"der({others[0].name})") in derivative_symbols:
            continue
        coefficient = partial(eq, others[0])
        if coefficient == 0 or any(s not in parameter_values for s in free_symbols(coefficient)):
            continue
        definitions[others[0]] = (i, -eq.xreplace({others[0]: sympy.Integer(0)}) / coefficient)
    return definitions


def _remove_dependencies(equations, derivative_symbols, parameter_values, tol) -> tuple[list[sympy.Expr], RankReport]:
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
            if not math.isfinite(value):
                break                                   # overflowed (C = 1e308 times a factor): no rank
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
