import numpy as np
import pytest
import scipy.sparse
from hypothesis import given, settings
from scipy.sparse.csgraph import connected_components

from compiler.structure.graph import (
    UNMATCHED,
    block_lower_triangular,
    maximum_matching,
    strongly_connected_components,
)
from graph_strategies import digraphs, nonsingular_square_systems


def assert_reverse_topological(n, successors, components):
    position = {}
    for k, component in enumerate(components):
        for node in component:
            assert node not in position
            position[node] = k
    assert sorted(position) == list(range(n))
    for node in range(n):
        for successor in successors[node]:
            assert position[successor] <= position[node], f"edge {node}->{successor} goes forward"


def test_textbook_graph():
    # CLRS figure 22.9 (a..h = 0..7): components {a,b,e}, {c,d}, {f,g}, {h}.
    successors = [[1], [2, 4, 5], [3, 6], [2, 7], [0, 5], [6], [5, 7], [7]]
    components = strongly_connected_components(8, successors)
    assert components == [[7], [5, 6], [2, 3], [0, 1, 4]]
    assert_reverse_topological(8, successors, components)


def test_deep_path_needs_no_recursion():
    n = 50000
    successors = [[i + 1] for i in range(n - 1)] + [[0]]
    assert strongly_connected_components(n, successors) == [list(range(n))]
    successors[-1] = []
    components = strongly_connected_components(n, successors)
    assert components == [[i] for i in reversed(range(n))]


@settings(max_examples=300, deadline=None)
@given(digraphs())
def test_components_match_scipy_and_are_ordered(graph):
    n, successors = graph
    components = strongly_connected_components(n, successors)
    assert_reverse_topological(n, successors, components)
    if n == 0:
        return
    rows = [u for u in range(n) for _ in successors[u]]
    cols = [v for u in range(n) for v in successors[u]]
    matrix = scipy.sparse.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n))
    count, labels = connected_components(matrix, directed=True, connection="strong")
    assert len(components) == count
    for component in components:
        assert len({labels[node] for node in component}) == 1


def assert_solve_order(incidence, eq_to_var, blocks):
    matched_vars = {var for var in eq_to_var if var != UNMATCHED}
    known = set()
    seen_eqs = []
    for eqs, block_vars in blocks:
        assert block_vars == [eq_to_var[eq] for eq in eqs]
        block_set = set(block_vars)
        for eq in eqs:
            for var in incidence[eq]:
                assert var in known or var in block_set or var not in matched_vars
        known |= block_set
        seen_eqs += eqs
    assert sorted(seen_eqs) == list(range(len(incidence)))


def test_triangular_system_splits_into_scalar_blocks_in_dependency_order():
    # eq0: a + b, eq1: b, eq2: a + c  ->  solve b, then a, then c.
    incidence = [[0, 1], [1], [0, 2]]
    eq_to_var = [0, 1, 2]
    blocks = block_lower_triangular(3, incidence, eq_to_var)
    assert blocks == [([1], [1]), ([0], [0]), ([2], [2])]


def test_algebraic_loop_forms_one_block_and_unmatched_variables_are_inputs():
    # eq0: x + y + s, eq1: x - y, eq2: z + x; s (var 3) is a state no equation is matched to.
    incidence = [[0, 1, 3], [0, 1], [0, 2]]
    eq_to_var = [0, 1, 2]
    blocks = block_lower_triangular(3, incidence, eq_to_var)
    assert blocks == [([0, 1], [0, 1]), ([2], [2])]


def test_unmatched_equation_is_rejected():
    with pytest.raises(ValueError):
        block_lower_triangular(2, [[0], [0]], [0, UNMATCHED])


@settings(max_examples=300, deadline=None)
@given(nonsingular_square_systems())
def test_blt_blocks_only_use_earlier_variables(system):
    n, incidence = system
    eq_to_var, _ = maximum_matching(n, n, incidence)
    assert UNMATCHED not in eq_to_var
    blocks = block_lower_triangular(n, incidence, eq_to_var)
    assert_solve_order(incidence, eq_to_var, blocks)
