"""The layout of the dummy-derivative choice that every state-set variant carries, so that the
runtime can make the choice again at a switch point (compiler/runtime/variants.py::dummy_choice).

It mirrors compiler/structure/dummy_derivatives.py::select_dummy_derivatives: the levels' rows do
not depend on the choice, the first level's candidates neither; each later level's candidates are
the undifferentiated versions of the columns chosen one level up that occur in its rows. Here every
level lists all candidates any choice can offer it, in the selection's order of preference
(priority, then more-differentiated first, then by name), with the next level's candidate of each.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from compiler.runtime.variants import selection_output
from compiler.structure.differentiate import partial
from compiler.structure.indexed import IndexedSystem
from compiler.structure.reduced import Assignment


@dataclass(frozen=True)
class SelectionLevel:
    rows: tuple[int, ...]                 # equation indices
    order: tuple[int, ...]                # every candidate this level can be offered, preferred first
    next: dict[int, int]                  # candidate -> its candidate on the next level
    priority: dict[int, int]              # candidate -> the state priority of its base variable


def selection_levels(system: IndexedSystem, priority: Callable[[int], int]) -> list[SelectionLevel]:
    diff_to_eq = system.diff_to_eq()
    diff_to_var = system.diff_to_var()
    rows = [e for e in range(system.n_eqs) if diff_to_eq[e] >= 0 and system.eq_to_diff[e] < 0]
    candidates = sorted({v for e in rows for v in system.incidence[e]
                         if system.var_to_diff[v] < 0 and diff_to_var[v] >= 0})
    levels = []
    while rows:
        order = sorted(candidates, key=lambda v: (priority(v), -system.names[v].count("der("),
                                                  system.names[v]))
        next_rows = [diff_to_eq[e] for e in rows if diff_to_eq[diff_to_eq[e]] >= 0]
        occurring = {v for e in next_rows for v in system.incidence[e]}
        following = {v: diff_to_var[v] for v in candidates
                     if diff_to_var[diff_to_var[v]] >= 0 and diff_to_var[v] in occurring}
        levels.append(SelectionLevel(tuple(rows), tuple(order), following,
                                     {v: priority(v) for v in order}))
        rows, candidates = next_rows, sorted(set(following.values()))
    return levels


def selection_assignments(system: IndexedSystem, levels: list[SelectionLevel]) -> list[Assignment]:
    """One output per structurally non-zero entry of every level's Jacobian."""
    out = []
    for k, level in enumerate(levels):
        wanted = set(level.order)
        for i, e in enumerate(level.rows):
            for v in sorted(system.incidence[e]):
                if v in wanted:
                    out.append(Assignment(selection_output(k, i, system.names[v]),
                                          partial(system.equations[e], system.symbols[v])))
    return out


def selection_metadata(system: IndexedSystem, levels: list[SelectionLevel], public: list[str]) -> dict:
    """The runtime's plain form of the layout (CompiledModel.metadata[variants.SELECTION])."""
    names = system.names
    return {"public": list(public),
            "levels": [{"rows": len(level.rows), "order": [names[v] for v in level.order],
                        "priority": {names[v]: int(level.priority[v]) for v in level.order},
                        "next": {names[v]: names[w] for v, w in sorted(level.next.items())}}
                       for level in levels]}
