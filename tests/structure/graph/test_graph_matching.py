import numpy as np
import pytest
import scipy.sparse
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.sparse.csgraph import maximum_bipartite_matching

from compiler.structure.graph import UNMATCHED, augmenting_path, maximum_matching
from graph_strategies import incidences


def scipy_matching_size(n_eqs, n_vars, incidence, allowed=None):
    rows, cols = [], []
    for eq, row in enumerate(incidence):
        for var in row:
            if allowed is None or allowed[var]:
                rows.append(eq)
                cols.append(var)
    if n_eqs == 0:
        return 0
    matrix = scipy.sparse.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(n_eqs, n_vars))
    return int((maximum_bipartite_matching(matrix, perm_type="column") >= 0).sum())


def assert_valid_matching(incidence, eq_to_var, var_to_eq, allowed=None):
    for eq, var in enumerate(eq_to_var):
        if var == UNMATCHED:
            continue
        assert var in incidence[eq], f"eq {eq} matched to {var} which it does not contain"
        assert var_to_eq[var] == eq
        assert allowed is None or allowed[var]
    for var, eq in enumerate(var_to_eq):
        if eq != UNMATCHED:
            assert eq_to_var[eq] == var


def matched_count(eq_to_var):
    return sum(1 for var in eq_to_var if var != UNMATCHED)


def test_textbook_example_needs_an_augmenting_path():
    # Greedy takes eq0 -> v0, then eq1 (only v0) must re-route eq0 to v1.
    incidence = [[0, 1], [0], [1, 2]]
    eq_to_var, var_to_eq = maximum_matching(3, 3, incidence)
    assert eq_to_var == [1, 0, 2]
    assert var_to_eq == [1, 0, 2]


def test_excluded_variables_are_never_matched():
    incidence = [[0, 1], [1]]
    eq_to_var, var_to_eq = maximum_matching(2, 2, incidence, var_allowed=[False, True])
    assert matched_count(eq_to_var) == 1
    assert var_to_eq[0] == UNMATCHED


def test_weights_express_a_preference_among_free_variables():
    incidence = [[0, 1, 2]]
    assert maximum_matching(1, 3, incidence)[0] == [0]
    assert maximum_matching(1, 3, incidence, var_weight=[0, 5, 3])[0] == [1]


def test_weights_never_cost_cardinality():
    # Preferring v0 for eq0 would leave eq1 unmatched; Hopcroft–Karp re-routes it.
    incidence = [[0, 1], [0]]
    eq_to_var, _ = maximum_matching(2, 2, incidence, var_weight=[10, 0])
    assert eq_to_var == [1, 0]


def test_equation_order_selects_among_maximum_matchings():
    incidence = [[0], [0]]
    assert maximum_matching(2, 1, incidence)[0] == [0, UNMATCHED]
    assert maximum_matching(2, 1, incidence, eq_order=[1, 0])[0] == [UNMATCHED, 0]


def test_long_chain_needs_no_recursion():
    # eq i contains v_i and v_{i+1}; greedy by reverse order blocks everything: one long path.
    n = 20000
    incidence = [[i, i + 1] if i + 1 < n else [i] for i in range(n)]
    incidence_rev = [list(reversed(row)) for row in incidence]
    eq_to_var, var_to_eq = maximum_matching(n, n, incidence_rev)
    assert matched_count(eq_to_var) == n
    assert_valid_matching(incidence, eq_to_var, var_to_eq)


def test_augmenting_path_reroutes_and_reports_visits():
    incidence = [[0, 1], [0]]
    eq_to_var = [0, UNMATCHED]
    var_to_eq = [0, UNMATCHED]
    found, visited_eqs, visited_vars = augmenting_path(1, incidence, eq_to_var, var_to_eq)
    assert found
    assert eq_to_var == [1, 0] and var_to_eq == [1, 0]
    assert visited_eqs == [1, 0]


def test_failed_augmenting_path_returns_the_hall_set():
    # eq0 and eq1 compete for v0 (v1 excluded); eq2 is unrelated and must not be visited.
    incidence = [[0, 1], [0, 1], [2]]
    allowed = [True, False, True]
    eq_to_var = [0, UNMATCHED, 2]
    var_to_eq = [0, UNMATCHED, 2]
    found, visited_eqs, visited_vars = augmenting_path(1, incidence, eq_to_var, var_to_eq, allowed)
    assert not found
    assert sorted(visited_eqs) == [0, 1]
    assert visited_vars == [0]
    assert eq_to_var == [0, UNMATCHED, 2]


def test_augmenting_path_refuses_a_matched_equation():
    with pytest.raises(ValueError):
        augmenting_path(0, [[0]], [0], [0])


@settings(max_examples=300, deadline=None)
@given(incidences(), st.data())
def test_hopcroft_karp_is_maximum(structure, data):
    n_eqs, n_vars, incidence = structure
    allowed = data.draw(st.lists(st.booleans(), min_size=n_vars, max_size=n_vars))
    weights = data.draw(st.none() | st.lists(st.integers(0, 3), min_size=n_vars, max_size=n_vars))
    order = data.draw(st.permutations(list(range(n_eqs))))
    eq_to_var, var_to_eq = maximum_matching(n_eqs, n_vars, incidence, var_allowed=allowed,
                                            eq_order=order, var_weight=weights)
    assert_valid_matching(incidence, eq_to_var, var_to_eq, allowed)
    assert matched_count(eq_to_var) == scipy_matching_size(n_eqs, n_vars, incidence, allowed)


@settings(max_examples=300, deadline=None)
@given(incidences())
def test_repeated_augmenting_paths_reach_a_maximum_matching(structure):
    n_eqs, n_vars, incidence = structure
    eq_to_var = [UNMATCHED] * n_eqs
    var_to_eq = [UNMATCHED] * n_vars
    for eq in range(n_eqs):
        before = matched_count(eq_to_var)
        found, visited_eqs, visited_vars = augmenting_path(eq, incidence, eq_to_var, var_to_eq)
        assert matched_count(eq_to_var) == before + found
        assert visited_eqs[0] == eq
        if not found:
            # Hall's obstruction: the visited equations only reach the visited (matched) variables.
            reached = {var for visited in visited_eqs for var in incidence[visited]}
            assert reached == set(visited_vars)
            assert len(visited_eqs) == len(visited_vars) + 1
    assert_valid_matching(incidence, eq_to_var, var_to_eq)
    assert matched_count(eq_to_var) == scipy_matching_size(n_eqs, n_vars, incidence)


def test_equations_left_out_of_the_order_stay_unmatched():
    incidence = [[0, 1], [1], [0]]
    eq_to_var, var_to_eq = maximum_matching(3, 2, incidence, eq_order=[2, 0])
    assert eq_to_var == [1, UNMATCHED, 0]
    assert var_to_eq == [2, 0]
