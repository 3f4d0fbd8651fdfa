"""Located errors for structurally singular systems, built on the Dulmage–Mendelsohn partition."""
from __future__ import annotations

from compiler.errors import DyadError, Note
from compiler.structure.graph.dulmage_mendelsohn import dulmage_mendelsohn
from compiler.structure.indexed import IndexedSystem

_MAX_LISTED = 8


def structural_singularity_error(system: IndexedSystem, describe_equation=None,
                                 unknown_mask: list[bool] | None = None) -> DyadError:
    """Name the over-determined equations and the under-determined unknowns with their origins."""
    incidence = system.incidence
    if unknown_mask is not None:
        incidence = [[v for v in row if unknown_mask[v]] for row in incidence]
    dm = dulmage_mendelsohn(system.n_eqs, system.n_vars, incidence)
    over_eqs = list(dm.overdetermined_eqs)
    under_vars = [v for v in dm.underdetermined_vars if unknown_mask is None or unknown_mask[v]]
    notes = []
    for e in over_eqs[:_MAX_LISTED]:
        origin = system.origins[e]
        text = describe_equation(e) if describe_equation else str(system.equations[e])
        notes.append(Note(f"over-determined: {text}  (from {origin.path or '<model>'})",
                          origin.span if origin else None))
    parts = []
    if over_eqs:
        parts.append(f"{len(over_eqs)} equation(s) over-determine their unknowns")
    if under_vars:
        names = ", ".join(system.names[v] for v in under_vars[:_MAX_LISTED])
        more = f" and {len(under_vars) - _MAX_LISTED} more" if len(under_vars) > _MAX_LISTED else ""
        parts.append(f"{len(under_vars)} unknown(s) have no equation to determine them: {names}{more}")
    message = "the model is structurally singular: " + ("; ".join(parts) or "no perfect matching exists")
    first = next((n.span for n in notes if n.span), None)
    return DyadError(message, first, hint="check for missing or duplicated equations, or a redundant "
                     "connection between already constrained frames", notes=notes)
