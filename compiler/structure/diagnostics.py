"""Located errors for singular systems, built on the Dulmage–Mendelsohn partition: structurally
singular ones, and ones made singular by parameter values (a coefficient that vanishes)."""
from __future__ import annotations

import sympy

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


def parameter_singularity_error(system: IndexedSystem, unknown_mask: list[bool],
                                parameter_values: dict[str, float]) -> DyadError | None:
    """The system is structurally fine, but with these parameter values some coefficients of its
    unknowns vanish identically (a mass of 0 in `m*der(v) = f`) and no matching is left: the
    index-1 system is singular at every point, the solver can only fail at its first step.

    A Jacobian entry is dropped only when, after substituting the parameter values, it is zero as
    an expression in the unknowns; so a None answer means "not explained by the parameters", never
    a false alarm. Returns the located error naming the equations and the parameters, or None."""
    values = {sympy.Symbol(k): v for k, v in parameter_values.items()}
    columns = {v: j for j, v in enumerate(v for v in range(system.n_vars) if unknown_mask[v])}
    pruned: list[list[int]] = []
    vanished: dict[int, list[tuple[int, set]]] = {}
    for e, row in enumerate(system.incidence):
        equation = system.equations[e]
        has_parameters = bool(equation.free_symbols & values.keys())
        kept = []
        for v in row:
            if v not in columns:
                continue
            if has_parameters:
                partial = sympy.diff(equation, system.symbols[v])
                used = partial.free_symbols & values.keys()
                if used:
                    at = partial.xreplace({s: values[s] for s in used})
                    if at == 0 or sympy.expand(at) == 0:
                        vanished.setdefault(e, []).append((v, used))
                        continue
            kept.append(columns[v])
        pruned.append(kept)
    if not vanished:
        return None
    dm = dulmage_mendelsohn(system.n_eqs, len(columns), pruned)
    if dm.is_square_and_nonsingular and system.n_eqs == len(columns):
        return None
    suspects = set(dm.overdetermined_eqs) | set(dm.underdetermined_eqs)
    culprits = [e for e in vanished if e in suspects] or sorted(vanished)
    return _vanished_coefficient_error(system, culprits, vanished, values)


def _vanished_coefficient_error(system, culprits, vanished, values) -> DyadError:
    def blamed(e: int) -> list[sympy.Symbol]:
        used = set().union(*(u for _, u in vanished[e]))
        zeros = [s for s in used if values[s] == 0]
        return sorted(zeros or used, key=lambda s: s.name)

    def text(e: int) -> str:
        lost = ", ".join(f"`{system.names[v]}`" for v, _ in vanished[e])
        settings = ", ".join(f"`{s.name}` = {values[s]:g}" for s in blamed(e))
        return (f"with {settings}, equation `{system.equations[e]} = 0` "
                f"({system.origins[e].path or '<model>'}) no longer contains {lost}")

    first = culprits[0]
    origin = system.origins[first]
    names = sorted({s.name for e in culprits for s in blamed(e)})
    notes = [Note(text(e), system.origins[e].span if system.origins[e] else None)
             for e in culprits[1:_MAX_LISTED]]
    listed = ", ".join(f"`{n}`" for n in names)
    return DyadError(f"the model is singular at the start: {text(first)}, so nothing determines "
                     f"it", origin.span if origin else None, notes=notes,
                     hint=f"the value of {listed} makes a coefficient vanish: give "
                          f"{'it' if len(names) == 1 else 'them'} a nonzero value "
                          f"(e.g. -p {names[0]}=...) or check the equation")
