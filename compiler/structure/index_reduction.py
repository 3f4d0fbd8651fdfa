"""Pantelides on the integer structure, then the symbolic differentiation it asks for."""
from __future__ import annotations

from dataclasses import dataclass

from compiler.errors import DyadError
from compiler.flat import der_name
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
    except StructurallySingular as err:
        unmatched = list(getattr(err, "unmatched_eqs", []) or [])
        raise _singular_error(system, unmatched, describe_equation) from None

    names = list(system.names)
    names.extend([None] * (result.n_vars - len(names)))
    for v in range(result.n_vars):
        d = result.var_to_diff[v]
        if d >= 0 and names[d] is None:
            names[d] = der_name(names[v])
    reduced = IndexedSystem(names, list(result.var_to_diff), list(system.equations) + [None] * (result.n_eqs - system.n_eqs),
                            list(system.origins) + [None] * (result.n_eqs - system.n_eqs),
                            list(result.eq_to_diff), incidence=[[0]])  # incidence recomputed below
    for original, derived in result.differentiation_order:
        reduced.equations[derived] = reduced.time_derivative(reduced.equations[original])
        reduced.origins[derived] = reduced.origins[original]
    reduced.incidence = [reduced.incidence_of(e) for e in reduced.equations]
    report = IndexReductionReport(structural_index(result), result.n_eqs - system.n_eqs,
                                  reduced.n_vars - n_vars_before)
    return reduced, report


def _singular_error(system: IndexedSystem, unmatched_eqs: list[int], describe_equation) -> DyadError:
    from compiler.structure.diagnostics import structural_singularity_error
    return structural_singularity_error(system, describe_equation)
