"""The regular column subsets found along the combinations
(compiler/structure/state_selection/regular_subsets.py) are those a loop over
itertools.combinations finds with one full matching per subset (Hopcroft–Karp): the same subsets,
in the same order, and a search that stops at the same subset when its budget runs out."""
from __future__ import annotations

import itertools

from hypothesis import given, settings
from hypothesis import strategies as st

from compiler.structure.graph.matching import UNMATCHED, maximum_matching
from compiler.structure.state_selection.regular_subsets import regular_subsets


class Exhausted(Exception):
    pass


def full_matching_size(positions, columns) -> int:
    rows_of = [list(positions.get(v, ())) for v in columns]
    n_rows = 1 + max((i for found in rows_of for i in found), default=-1)
    column_to_row, _ = maximum_matching(len(columns), n_rows, rows_of)
    return sum(1 for i in column_to_row if i != UNMATCHED)


def by_every_subset(positions, n_rows, fixed, rest, size, budget):
    """The loop the search replaces: every subset counted, then tested with its own matching."""
    found = []
    try:
        for subset in itertools.combinations(rest, size):
            budget -= 1
            if budget < 0:
                raise Exhausted
            if full_matching_size(positions, list(fixed) + list(subset)) == n_rows:
                found.append(subset)
    except Exhausted:
        return found, True
    return found, False


def along_the_combinations(positions, fixed, rest, size, budget):
    left = [budget]

    def spend(n: int) -> None:
        left[0] -= n
        if left[0] < 0:
            raise Exhausted
    found = []
    try:
        for subset in regular_subsets(positions, fixed, rest, size, spend):
            found.append(subset)
    except Exhausted:
        return found, True
    return found, False


@st.composite
def levels(draw):
    n_rows = draw(st.integers(0, 6))
    n_columns = draw(st.integers(0, 10))
    incidence = [[c for c in range(n_columns) if draw(st.booleans())] for _ in range(n_rows)]
    positions: dict[int, list[int]] = {}
    for i, row in enumerate(incidence):
        for c in row:
            positions.setdefault(c, []).append(i)
    columns = draw(st.permutations(list(range(n_columns))))
    n_fixed = draw(st.integers(0, min(n_rows, n_columns)))
    return positions, n_rows, columns[:n_fixed], columns[n_fixed:], n_rows - n_fixed


@settings(max_examples=400, deadline=None)
@given(levels(), st.integers(0, 60))
def test_the_same_subsets_in_the_same_order_and_the_same_stop(level, budget):
    positions, n_rows, fixed, rest, size = level
    assert along_the_combinations(positions, fixed, rest, size, budget) == \
        by_every_subset(positions, n_rows, fixed, rest, size, budget)


def test_a_chain_of_two_body_rows_keeps_only_the_regular_choices():
    # rows 0 and 1 each hold columns {0, 1} and {1, 2}: of the pairs, {0, 2} and {0, 1}, {1, 2} match
    positions = {0: [0], 1: [0, 1], 2: [1], 3: []}
    found, stopped = along_the_combinations(positions, [], [0, 1, 2, 3], 2, 100)
    assert found == [(0, 1), (0, 2), (1, 2)] and not stopped
