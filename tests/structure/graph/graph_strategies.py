"""Hypothesis strategies for random integer incidence structures (shared by the graph tests)."""
from __future__ import annotations

from hypothesis import strategies as st


@st.composite
def incidences(draw, max_eqs: int = 12, max_vars: int = 12, max_degree: int = 4):
    """(n_eqs, n_vars, incidence) with sorted, duplicate-free rows (rows may be empty)."""
    n_eqs = draw(st.integers(0, max_eqs))
    n_vars = draw(st.integers(1, max_vars))
    rows = [sorted(draw(st.sets(st.integers(0, n_vars - 1), max_size=max_degree)))
            for _ in range(n_eqs)]
    return n_eqs, n_vars, rows


@st.composite
def nonsingular_square_systems(draw, max_size: int = 14, max_extra: int = 3):
    """A square incidence with a hidden perfect matching (a permuted diagonal) plus extra entries."""
    n = draw(st.integers(1, max_size))
    hidden = draw(st.permutations(list(range(n))))
    rows = []
    for eq in range(n):
        extra = draw(st.sets(st.integers(0, n - 1), max_size=max_extra))
        rows.append(sorted(extra | {hidden[eq]}))
    return n, rows


@st.composite
def digraphs(draw, max_nodes: int = 15, max_out: int = 3):
    n = draw(st.integers(0, max_nodes))
    if n == 0:
        return 0, []
    successors = [sorted(draw(st.sets(st.integers(0, n - 1), max_size=max_out))) for _ in range(n)]
    return n, successors
