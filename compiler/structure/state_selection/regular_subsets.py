"""The column subsets of a state-set level whose block is structurally regular, found along the
combinations instead of one matching per subset (enumeration.py).

`itertools.combinations(rest, size)` lists the subsets in lexicographic order; consecutive ones
share a prefix. A maximum matching of rows to the `fixed` columns and a prefix is kept and extended
by one augmenting path per column added (structure/graph/matching.py); where a column cannot be
matched, no subset with that prefix has a regular block (Hall's condition fails on the prefix),
so all of them are counted at once and skipped. The regular subsets come out in the same order,
and every subset is counted in the same order, as a loop over `combinations` testing each with its
own matching; the count stops the search where that loop would (`spend`).
"""
from __future__ import annotations

from math import comb
from typing import Callable, Iterator, Mapping, Sequence

from compiler.structure.graph.matching import UNMATCHED, augmenting_path


def regular_subsets(positions: Mapping[int, Sequence[int]], fixed: Sequence[int], rest: Sequence[int],
                    size: int, spend: Callable[[int], None]) -> Iterator[tuple[int, ...]]:
    """The subsets of `size` columns of `rest` that, with `fixed`, match every row (`positions`:
    column -> the positions of the rows it occurs in); spend(n) is told of every n subsets looked
    at (it raises to stop the search)."""
    if size < 0:
        return
    columns = list(fixed) + list(rest)
    rows_of = [list(positions.get(v, ())) for v in columns]
    n_rows = 1 + max((i for found in rows_of for i in found), default=-1)
    column_to_row, row_to_column = [UNMATCHED] * len(columns), [UNMATCHED] * n_rows

    def augment(j: int) -> bool:
        return augmenting_path(j, rows_of, column_to_row, row_to_column)[0]

    if not all([augment(j) for j in range(len(fixed))]):
        spend(comb(len(rest), size))      # every subset looked at, none regular
        return
    chosen: list[int] = []
    first = len(fixed)                    # rest[k] is column first + k

    def extend(start: int) -> Iterator[tuple[int, ...]]:
        if len(chosen) == size:
            spend(1)
            yield tuple(chosen)
            return
        left = size - len(chosen)
        for k in range(start, len(rest) - left + 1):
            before = column_to_row[:], row_to_column[:]
            if augment(first + k):
                chosen.append(rest[k])
                yield from extend(k + 1)
                chosen.pop()
                column_to_row[:], row_to_column[:] = before
            else:
                spend(comb(len(rest) - k - 1, left - 1))     # the subsets with this prefix
    yield from extend(0)
