"""Every state set a run of a model can switch to, listed at compile time so that the compiled
model can carry them (`CompiledModel.variants`, built by compiler/lower/state_set_variants.py)
and generated modules and C code switch as the in-process run does, with the runtime only.

The runtime's choice at a switch point (runtime/variants.py::dummy_choice, the compiler's
dummy-derivative selection made again, with alias rows folded: folds.py) takes, level by level, a
set of columns whose block is regular there. Which sets a point can give is not known in advance,
so every set whose folded block is structurally regular is a possible choice, less what pivoting
provably never gives: the columns of leading priority classes it always takes whole (constant
Jacobian, or independent at every point). The sets' product over the levels (each level's
candidates follow from the choice one level up) is the list of variants: 2 for a pendulum, 14
for a 3-body Cartesian chain, (3^N + 1) / 2 for N bodies. A model with more than the variant
limit carries none of them but its index-1 system, from which the runtime makes any state set it
reaches (compiler/lower/universal_variant.py, runtime/universal.py).
"""
from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Iterator

import numpy as np
import sympy

from compiler.runtime.selection_rules import (folded_level, level_choice, next_candidates, present_folds,
                                              priority_classes)
from compiler.structure.differentiate import partial
from compiler.structure.indexed import IndexedSystem
from compiler.structure.state_selection.folds import alias_folds, plain_number, unfolded
from compiler.structure.state_selection.forcing import row_positions
from compiler.structure.state_selection.layout import SelectionLevel
from compiler.structure.state_selection.regular_subsets import regular_subsets

if TYPE_CHECKING:
    from compiler.model.flat import FlatSystem

TRIES = 5_000           # subsets looked at before giving up (most are singular in a long chain)


class TooManyToList(Exception):
    """The possible state sets were not all found within the subsets looked at."""


def possible_choices(flat: FlatSystem, system: IndexedSystem, levels: list[SelectionLevel],
                     tries: int = TRIES) -> Iterator[frozenset[str]]:
    """Every dummy-derivative set (names) the runtime's choice can make: on each level, folded
    (folds.py: every u taken, the choice made without the alias rows and w columns), the columns
    that pivoting takes from the leading priority classes whose Jacobian is constant (computed
    here, at the parameters' defaults), completed by every set of later columns that makes the
    folded block structurally regular; the next level's candidates follow from the columns that
    propagate (selection_rules.next_candidates). Raises TooManyToList after looking at `tries`
    subsets."""
    constant = _constant_entries(flat, system)
    budget = [tries]

    def spend(looked_at: int) -> None:
        budget[0] -= looked_at
        if budget[0] < 0:
            raise TooManyToList

    folds_of = [alias_folds(system, level.rows, level.order, level.priority.get) for level in levels]

    def walk(k: int, candidates: set[int], dummies: tuple[int, ...]):
        if k == len(levels):
            yield frozenset(system.names[v] for v in dummies)
            return
        level = levels[k]
        folds = present_folds(folds_of[k], candidates)
        partner = {u: w for _, u, w in folds}
        offered = [v for v in level.order if v in candidates]
        level_folded = folded_level(range(len(level.rows)), offered, [], folds)
        rows = [level.rows[i] for i in level_folded.rows]
        order = level_folded.candidates
        folded = dataclasses.replace(level, rows=tuple(rows))
        fixed, rest = _constant_prefix_choice(system, folded, order, constant)
        fixed, rest = _independent_classes(system, folded, fixed, rest)
        positions = row_positions(system, rows)
        for subset in regular_subsets(positions, fixed, rest, len(rows) - len(fixed), spend):
            chosen = unfolded(fixed + list(subset), folds)
            yield from walk(k + 1, next_candidates(chosen, partner, level.next), dummies + tuple(chosen))
    if levels:
        yield from walk(0, set(levels[0].order), ())


def _constant_entries(flat: FlatSystem, system: IndexedSystem):
    """(equation, unknown) -> the value of d equation / d unknown where it does not depend on the
    unknowns (at the parameters' defaults), else None; memoized."""
    values = {sympy.Symbol(p.name): p.value for p in flat.parameters if p.value is not None}
    memo: dict[tuple[int, int], float | None] = {}

    def entry(e: int, v: int) -> float | None:
        if (e, v) not in memo:
            # a bare parameter's derivative xreplaced by its value is that (Python) number
            derivative = sympy.sympify(partial(system.equations[e], system.symbols[v]).xreplace(values))
            try:
                memo[e, v] = float(derivative) if not derivative.free_symbols else None
            except (TypeError, ValueError):
                memo[e, v] = None                  # not a finite number here: as if it varied
            if memo[e, v] is not None and not np.isfinite(memo[e, v]):
                memo[e, v] = None
        return memo[e, v]
    return entry


def _constant_prefix_choice(system: IndexedSystem, level: SelectionLevel, order: list[int], constant):
    """The columns pivoting takes from the leading priority classes of `order` whose entries are all
    constant (the same at every point), and the columns after those classes."""
    classes = priority_classes([level.priority[v] for v in order])
    matrix = np.zeros((len(level.rows), len(order)))
    prefix: list[list[int]] = []
    for members in classes:
        entries = [(i, j, constant(e, order[j]) if order[j] in system.incidence[e] else 0.0)
                   for j in members for i, e in enumerate(level.rows)]
        if any(value is None for _, _, value in entries):
            break
        for i, j, value in entries:
            matrix[i, j] = value
        prefix.append(members)
    if not prefix:
        return [], order
    end = prefix[-1][-1] + 1
    picked = level_choice(matrix[:, :end], [level.priority[v] for v in order[:end]], len(level.rows))
    return [order[j] for j in sorted(picked)], order[end:]


def _independent_classes(system: IndexedSystem, level: SelectionLevel, fixed: list[int], rest: list[int]):
    """`fixed` and `rest` with the leading priority classes of `rest` that pivoting takes whole
    moved to `fixed`: a class that fits in the rows left and whose columns, with `fixed`, are
    independent at every point and parameter value (_triangular). Pivoting then finds a part
    orthogonal to the columns taken in every column of the class (the threshold, 1e-8 of the
    largest entry, aside) and takes them all."""
    fixed, moved = list(fixed), 0
    for positions in priority_classes([level.priority[v] for v in rest]):
        members = [rest[j] for j in positions]
        if len(fixed) + len(members) > len(level.rows) or \
                not _triangular(system, level.rows, fixed + members):
            break
        fixed, moved = fixed + members, moved + len(members)
    return fixed, list(rest[moved:])


def _triangular(system: IndexedSystem, rows, columns) -> bool:
    """Whether `columns` peel off one by one, each on a row of its own among the columns left where
    its entry is a non-zero number: their block on those rows is then triangular with that
    number on the diagonal, its determinant never zero."""
    left, free_rows = set(columns), list(rows)
    while left:
        for v in sorted(left):
            row = next((e for e in free_rows if v in system.incidence[e]
                        and not any(u in system.incidence[e] for u in left if u != v)
                        and plain_number(system, e, v)), None)
            if row is not None:
                left.discard(v)
                free_rows.remove(row)
                break
        else:
            return False
    return True
