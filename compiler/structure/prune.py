"""Model only what the scene needs: assignments no state derivative or residual depends on are
moved out of the integrated system and evaluated after the solve, on request."""
from __future__ import annotations

import sympy

from compiler.model.symbols import free_symbols
from compiler.structure.reduced import Assignment


def prune_assignments(assignments: list[Assignment], roots: list[sympy.Expr]
                      ) -> tuple[list[Assignment], list[Assignment]]:
    needed: set[sympy.Symbol] = set()
    for expr in roots:
        needed |= free_symbols(expr)
    keep = [False] * len(assignments)
    for i in range(len(assignments) - 1, -1, -1):
        if sympy.Symbol(assignments[i].target) in needed:
            keep[i] = True
            needed |= free_symbols(assignments[i].expr)
    kept = [a for a, k in zip(assignments, keep) if k]
    pruned = [a for a, k in zip(assignments, keep) if not k]
    return kept, pruned
