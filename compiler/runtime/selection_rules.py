"""The rules of the dummy-derivative choice, written once for the compiler and the runtime.

The compiler chooses states and lists every state set a run can reach on the indices of its
index-1 system (compiler/structure/dummy_derivatives.py, compiler/structure/state_selection/);
the runtime makes the choice again where a run switches, on the names a compiled model carries
(variants.dummy_choice, universal.variant_of). Both call these functions, which see only plain
structures (positions, names, numbers): no sympy, no CasADi.

A level of the choice is a set of rows (differentiated constraints) and candidate columns
(derivatives); an alias fold (row, u, w) is a row that only says u and w are the same up to a
constant factor (compiler/structure/state_selection/folds.py finds them).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Generic, Hashable, Mapping, Sequence, TypeVar

from .state_sets import pivoted_columns

Column = TypeVar("Column", bound=Hashable)


def preference_order(candidates, priority: Callable, name: Callable[..., str]) -> list:
    """The candidates in the choice's order of preference: lowest state priority first (its
    derivative becomes a dummy first, so that hinted variables stay states); among equal
    priorities the more differentiated first (rather der(der(phi)) than der(w), so that named
    variables stay states), then by name."""
    return sorted(candidates, key=lambda c: (priority(c), -name(c).count("der("), name(c)))


def priority_classes(priorities: Sequence[int]) -> list[list[int]]:
    """Positions grouped by priority value, the lowest priority first and positions ascending in
    each class: the order in which pivoting takes columns. For candidates already in preference
    order the classes are its consecutive runs of equal priority."""
    classes: dict[int, list[int]] = {}
    for j in sorted(range(len(priorities)), key=lambda j: (priorities[j], j)):
        classes.setdefault(priorities[j], []).append(j)
    return list(classes.values())


def level_choice(matrix, priorities: Sequence[int], n_rows: int, folds: Sequence = ()) -> list[int]:
    """The numerical choice on one level: pivoted Gram–Schmidt (state_sets.pivoted_columns) over
    the level's Jacobian, priority class by class (`priorities` per column), `folds` as
    (row, u position, w position). Positions of the chosen columns; fewer than `n_rows` where no
    regular choice exists."""
    return pivoted_columns(matrix, priority_classes(priorities), n_rows, folds=folds)


def present_folds(folds: Sequence, candidates) -> list[tuple]:
    """The folds (row, u, w) that count among `candidates`: u and w both candidates."""
    present = set(candidates)
    return [(row, u, w) for row, u, w in folds if u in present and w in present]


@dataclass(frozen=True)
class FoldedLevel(Generic[Column]):
    rows: list                    # the level's rows without its alias rows
    candidates: list[Column]      # its candidates without the folded w columns
    chosen: list[Column]          # the choice as the folded choice makes it


def folded_level(rows: Sequence, candidates: Sequence[Column], chosen: Sequence[Column],
                 folds: Sequence) -> FoldedLevel[Column]:
    """A level as the folded choice sees it (`folds`: present_folds of the level): without the
    alias rows and w columns, its choice the u whose w is chosen and the other chosen columns."""
    partner = {u: w for _, u, w in folds}
    fold_rows = {row for row, _, _ in folds}
    folded_out = set(partner.values())
    taken = set(chosen)
    kept = [c for c in chosen if c not in folded_out and (c not in partner or partner[c] in taken)]
    return FoldedLevel([r for r in rows if r not in fold_rows],
                       [c for c in candidates if c not in folded_out], kept)


def propagating(chosen: Sequence[Column], partner: Mapping[Column, Column]) -> list[Column]:
    """The chosen columns whose next-level versions are the next level's candidates: a folded u
    only where its w is chosen too (x and vx are dummies together, as if vx were der(x))."""
    taken = set(chosen)
    return [c for c in chosen if c not in partner or partner[c] in taken]


def next_candidates(chosen: Sequence[Column], partner: Mapping[Column, Column],
                    next_of: Mapping[Column, Column]) -> set:
    """The next level's candidates after the choice `chosen` (`next_of`: a candidate's version on
    the next level, where it has one there)."""
    return {next_of[c] for c in propagating(chosen, partner) if c in next_of}


def stand_ins(pairs: Sequence[Sequence], kept) -> set:
    """Dummies that only stand in for a kept state: der(der(phi)) of a pair (der(w), der(der(phi)))
    (where w = +-der(phi) holds) whose der(w) is kept. Exchanging the two changes nothing, so
    they never call for a switch."""
    kept_set = set(kept)
    return {stand_in for kept_one, stand_in in pairs if kept_one in kept_set}


def may_degrade(n_rows: int, candidates: Sequence[Column], chosen: Sequence[Column],
                priority: Mapping[Column, int], stand_in_pairs: Sequence[Sequence],
                varies: Callable[[Column], bool]) -> bool:
    """Whether a folded level must be watched during a run: more candidates than rows, a chosen
    column (stand-ins for a kept state aside) whose entries `varies` (depend on the unknowns or
    time: a constant pivot block is valid everywhere), and not only a hinted state (a kept
    column of higher priority than every varying one) could take over."""
    if len(candidates) <= n_rows:
        return False
    chosen_set = set(chosen)
    kept = [c for c in candidates if c not in chosen_set]
    standing = stand_ins(stand_in_pairs, kept)
    varying = [c for c in chosen if c not in standing and varies(c)]
    if not varying:
        return False
    return not (kept and min(priority[c] for c in kept) > max(priority[c] for c in varying))


def watched_level(n_rows: int, candidates: Sequence[str], chosen: Sequence[int],
                  priorities: Sequence[int], entries: Sequence[int]) -> dict:
    """A watched level in the runtime's plain form (CompiledModel.state_sets, state_sets.py):
    `chosen` are candidate positions, `entries` the outputs holding the level's Jacobian
    (row-major), its candidate positions grouped in priority classes."""
    return {"rows": int(n_rows), "candidates": list(candidates), "chosen": list(chosen),
            "classes": priority_classes(priorities), "entries": list(entries)}
