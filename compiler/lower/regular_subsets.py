"""The column subsets of a state-set level whose block is structurally regular, found along the
combinations instead of one matching per subset (compiler/lower/state_set_enumeration.py).

`itertools.combinations(rest, size)` lists the subsets in lexicographic order; consecutive ones
share a prefix. A maximum matching of rows to the `fixed` columns and a prefix is kept and extended
by one augmenting path per column added; where a column cannot be matched, no subset with that
prefix has a regular block (Hall's condition fails on the prefix), so all of them are counted at
once and skipped. The regular subsets come out in the same order, and every subset is counted in
the same order, as a loop over `combinations` testing each with its own matching; the count stops
the search where that loop would (`spend`). A 32-body chain's first level (64 candidates, 32 rows)
took one full matching per subset, 5,000 subsets per search.
"""
from __future__ import annotations

from math import comb
from typing import Callable, Iterator, Mapping, Sequence


def augment_path(positions: Mapping[int, Sequence[int]], matched: dict[int, int], v: int, seen: set) -> bool:
    """Match column v to a row position, moving matched columns along an augmenting path (Kuhn's
    algorithm): `matched` (row position -> column) is updated in place; False where none exists."""
    for i in positions.get(v, ()):
        if i not in seen:
            seen.add(i)
            if i not in matched or augment_path(positions, matched, matched[i], seen):
                matched[i] = v
                return True
    return False


def regular_subsets(positions: Mapping[int, Sequence[int]], fixed: Sequence[int], rest: Sequence[int],
                    size: int, spend: Callable[[int], None]) -> Iterator[tuple[int, ...]]:
    """The subsets of `size` columns of `rest` that, with `fixed`, match every row (`positions`:
    column -> the positions of the rows it occurs in); spend(n) is told of every n subsets looked
    at (it raises to stop the search)."""
    if size < 0:
        return
    matched: dict[int, int] = {}          # row position -> column

    def augment(v: int, seen: set) -> bool:
        return augment_path(positions, matched, v, seen)

    if not all([augment(v, set()) for v in fixed]):
        spend(comb(len(rest), size))      # every subset looked at, none regular
        return
    chosen: list[int] = []

    def extend(start: int) -> Iterator[tuple[int, ...]]:
        if len(chosen) == size:
            spend(1)
            yield tuple(chosen)
            return
        left = size - len(chosen)
        for k in range(start, len(rest) - left + 1):
            before = dict(matched)
            if augment(rest[k], set()):
                chosen.append(rest[k])
                yield from extend(k + 1)
                chosen.pop()
                matched.clear()
                matched.update(before)
            else:
                spend(comb(len(rest) - k - 1, left - 1))     # the subsets with this prefix
    yield from extend(0)
