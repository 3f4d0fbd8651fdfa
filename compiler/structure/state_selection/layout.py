"""The layout of the dummy-derivative choice that every state-set variant carries, so that the
runtime can make the choice again at a switch point (compiler/runtime/variants.py::dummy_choice).

The levels are those of compiler/structure/dummy_derivatives.py (its first_level and next_rows):
their rows do not depend on the choice, the first level's candidates neither; each later level's
candidates are the undifferentiated versions of the columns chosen one level up that occur in its
rows. Here every level lists all candidates any choice can offer it, in the choice's order of
preference (candidate_order), with the next level's candidate of each.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable

from compiler.runtime.variants import selection_output
from compiler.structure.differentiate import partial
from compiler.structure.dummy_derivatives import candidate_order, first_level, next_rows, state_priority
from compiler.structure.state_selection.folds import alias_folds
from compiler.structure.indexed import IndexedSystem
from compiler.structure.reduced import Assignment

if TYPE_CHECKING:
    from compiler.structure.reduce import Analysis


@dataclass(frozen=True)
class SelectionLevel:
    rows: tuple[int, ...]                 # equation indices
    order: tuple[int, ...]                # every candidate this level can be offered, preferred first
    next: dict[int, int]                  # candidate -> its candidate on the next level
    priority: dict[int, int]              # candidate -> the state priority of its base variable


def choice_priority(analysis: Analysis) -> Callable[[int], int]:
    """The state priority of a candidate (dummy_derivatives.state_priority) for `analysis`."""
    return state_priority(analysis.system, analysis.priorities)


def selection_levels(system: IndexedSystem, priority: Callable[[int], int]) -> list[SelectionLevel]:
    """Every level of the choice with every candidate any choice can offer it."""
    diff_to_var = system.diff_to_var()
    rows, candidates = first_level(system)
    levels = []
    while rows:
        order = candidate_order(system, candidates, priority)
        following_rows = next_rows(system, rows)
        occurring = {v for e in following_rows for v in system.incidence[e]}
        following = {v: diff_to_var[v] for v in candidates
                     if diff_to_var[diff_to_var[v]] >= 0 and diff_to_var[v] in occurring}
        levels.append(SelectionLevel(tuple(rows), tuple(order), following,
                                     {v: priority(v) for v in order}))
        rows, candidates = following_rows, sorted(set(following.values()))
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
    """The runtime's plain form of the layout (CompiledModel.metadata[variants.SELECTION]), with
    each level's alias folds as [row, u, w] (folds.py)."""
    names = system.names
    return {"public": list(public),
            "levels": [{"rows": len(level.rows), "order": [names[v] for v in level.order],
                        "priority": {names[v]: int(level.priority[v]) for v in level.order},
                        "next": {names[v]: names[w] for v, w in sorted(level.next.items())},
                        "folds": [[i, names[u], names[w]] for i, u, w in
                                  alias_folds(system, level.rows, level.order, level.priority.get)]}
                       for level in levels]}
