"""A Jacobian under which the numerical dummy-derivative selection makes a given choice: how the
compiler builds the variant of a state set it listed (state_selection/enumeration.py) with the
one selection it has (structure/dummy_derivatives.py)."""
from __future__ import annotations

import numpy as np

from compiler.structure.graph.matching import UNMATCHED, maximum_matching
from compiler.structure.indexed import IndexedSystem


def row_positions(system: IndexedSystem, rows) -> dict[int, list[int]]:
    """Every unknown of `rows` -> the positions of the rows that contain it, in row order."""
    positions: dict[int, list[int]] = {}
    for i, e in enumerate(rows):
        for v in system.incidence[e]:
            positions.setdefault(v, []).append(i)
    return positions


def matched_rows(system: IndexedSystem, rows, columns) -> dict[int, int]:
    """A maximum matching column -> row position of `columns` on `rows`."""
    positions = row_positions(system, rows)
    column_to_row, _ = maximum_matching(len(columns), len(rows), [positions.get(v, []) for v in columns])
    return {v: i for v, i in zip(columns, column_to_row) if i != UNMATCHED}


def forcing(system: IndexedSystem, dummies: frozenset[str]):
    """A Jacobian (rows, cols) -> matrix under which the numerical selection picks `dummies`:
    a unit entry per chosen column on the row it is matched to, zero elsewhere."""
    def jacobian(rows: list[int], cols: list[int]) -> np.ndarray:
        chosen = [v for v in cols if system.names[v] in dummies]
        matrix = np.zeros((len(rows), len(cols)))
        for v, i in matched_rows(system, rows, chosen).items():
            matrix[i, cols.index(v)] = 1.0
        return matrix
    return jacobian
