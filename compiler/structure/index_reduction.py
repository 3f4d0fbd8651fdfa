"""Pantelides on the integer structure, then the symbolic differentiation it asks for."""
from __future__ import annotations

from dataclasses import dataclass

import sympy

from compiler.model.flat import der_name
from compiler.structure.diagnostics import structural_singularity_error
from compiler.structure.graph.pantelides import StructurallySingular, pantelides, structural_index
from compiler.structure.indexed import IndexedSystem


@dataclass
class IndexReductionReport:
    structural_index: int
    differentiated: int          # equations added by differentiation
    new_derivatives: int         # derivative unknowns added


def reduce_index(system: IndexedSystem, describe_equation=None) -> tuple[IndexedSystem, IndexReductionReport]:
    n_vars_before = system.n_vars
    try:
        result = pantelides(system.n_eqs, system.n_vars, system.incidence, list(system.var_to_diff))
    except StructurallySingular:
        raise structural_singularity_error(system, describe_equation) from None

    names = list(system.names)
    names.extend([None] * (result.n_vars - len(names)))
    for v in range(result.n_vars):
        d = result.var_to_diff[v]
        if d >= 0 and names[d] is None:
            names[d] = der_name(names[v])
    added = result.n_eqs - system.n_eqs
    # the added equations are placeholders until differentiated below, in creation order
    # incidence is set once below, after differentiation (a placeholder skips the first pass)
    reduced = IndexedSystem(names, list(result.var_to_diff), list(system.equations) + [sympy.Integer(0)] * added,
                            list(system.origins) + [None] * added, list(result.eq_to_diff),
                            incidence=[[]] * (system.n_eqs + added))
    for original, derived in result.differentiation_order:
        reduced.equations[derived] = reduced.time_derivative(reduced.equations[original])
        reduced.origins[derived] = reduced.origins[original]
    reduced.incidence = [reduced.incidence_of(e) for e in reduced.equations]
    report = IndexReductionReport(structural_index(result), result.n_eqs - system.n_eqs,
                                  reduced.n_vars - n_vars_before)
    return reduced, report

