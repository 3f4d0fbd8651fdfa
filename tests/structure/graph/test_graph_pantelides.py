import numpy as np
import pytest
import scipy.sparse
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.sparse.csgraph import maximum_bipartite_matching

from compiler.structure.graph import (
    UNMATCHED,
    StructurallySingular,
    derivative_families,
    invert_derivative_chain,
    pantelides,
    structural_index,
)


class Structure:
    """Builds an integer DAE structure from variable names; der(name) is its own variable."""

    def __init__(self):
        self.index: dict[str, int] = {}
        self.var_to_diff: list[int] = []
        self.incidence: list[list[int]] = []

    def var(self, name: str) -> int:
        if name not in self.index:
            self.index[name] = len(self.var_to_diff)
            self.var_to_diff.append(UNMATCHED)
            if name.startswith("der(") and name.endswith(")"):
                self.var_to_diff[self.var(name[4:-1])] = self.index[name]
        return self.index[name]

    def eq(self, *names: str) -> int:
        self.incidence.append(sorted({self.var(name) for name in names}))
        return len(self.incidence) - 1

    def run(self, **options):
        return pantelides(len(self.incidence), len(self.var_to_diff), self.incidence,
                          self.var_to_diff, **options)


def assert_consistent(result, n_eqs, n_vars, incidence):
    assert len(result.incidence) == len(result.eq_to_diff) == len(result.eq_to_var) == result.n_eqs
    assert len(result.var_to_diff) == len(result.var_to_eq) == result.n_vars
    assert result.incidence[:n_eqs] == [list(row) for row in incidence]
    for source, derivative in result.differentiation_order:
        assert result.eq_to_diff[source] == derivative
        expected = set(result.incidence[source])
        expected |= {result.var_to_diff[var] for var in result.incidence[source]}
        assert set(result.incidence[derivative]) == expected
        assert UNMATCHED not in expected
    assert len(result.differentiation_order) == result.n_eqs - n_eqs
    used = set()
    for eq in range(result.n_eqs):
        var = result.eq_to_var[eq]
        highest_eq = result.eq_to_diff[eq] == UNMATCHED
        if not highest_eq or not result.incidence[eq]:
            assert var == UNMATCHED
            continue
        assert var != UNMATCHED, f"highest equation {eq} left unmatched"
        assert var in result.incidence[eq]
        assert result.var_to_diff[var] == UNMATCHED, "matched a variable that has a derivative"
        assert var not in used
        used.add(var)
        assert result.var_to_eq[var] == eq


def pendulum():
    s = Structure()
    s.eq("der(x)", "u")
    s.eq("der(y)", "v")
    s.eq("der(u)", "T", "x")
    s.eq("der(v)", "T", "y")
    s.eq("x", "y")
    return s


def test_cartesian_pendulum_is_index_three():
    s = pendulum()
    result = s.run()
    assert_consistent(result, 5, len(s.var_to_diff), s.incidence)
    assert result.differentiation_counts()[:5] == [1, 1, 0, 0, 2]
    assert structural_index(result) == 3
    # The constraint, then the velocity equations it visits, then its second derivative.
    assert [source for source, _ in result.differentiation_order] == [4, 0, 1, 5]
    # New variables: der(der(x)) and der(der(y)), and the tension ends up matched.
    assert result.n_vars == len(s.var_to_diff) + 2
    second_x = result.var_to_diff[s.var("der(x)")]
    second_y = result.var_to_diff[s.var("der(y)")]
    assert {second_x, second_y} == {result.n_vars - 2, result.n_vars - 1}
    matched = {var for var in result.eq_to_var if var != UNMATCHED}
    assert matched == {s.var("T"), s.var("der(u)"), s.var("der(v)"), second_x, second_y}


def test_double_pendulum_differentiates_both_rod_constraints_twice():
    s = Structure()
    for mass in ("1", "2"):
        s.eq(f"der(x{mass})", f"u{mass}")
        s.eq(f"der(y{mass})", f"v{mass}")
    s.eq("der(u1)", "T1", "x1", "T2", "x2")
    s.eq("der(v1)", "T1", "y1", "T2", "y2")
    s.eq("der(u2)", "T2", "x1", "x2")
    s.eq("der(v2)", "T2", "y1", "y2")
    rod1 = s.eq("x1", "y1")
    rod2 = s.eq("x1", "y1", "x2", "y2")
    result = s.run()
    assert_consistent(result, len(s.incidence), len(s.var_to_diff), s.incidence)
    counts = result.differentiation_counts()
    assert counts[rod1] == counts[rod2] == 2
    assert structural_index(result) == 3
    assert {s.var("T1"), s.var("T2")} <= set(result.eq_to_var)


def test_index_one_system_needs_no_differentiation():
    # der(x) = -x + z, 0 = z - x^2
    s = Structure()
    s.eq("der(x)", "x", "z")
    s.eq("z", "x")
    result = s.run()
    assert result.differentiation_order == []
    assert result.n_eqs == 2 and result.n_vars == 3
    assert result.eq_to_var == [s.var("der(x)"), s.var("z")]
    assert structural_index(result) == 1


def test_explicit_ode_is_index_zero_including_second_order_chains():
    # der(der(x)) = -x written with an explicit chain x -> der(x) -> der(der(x)).
    s = Structure()
    s.eq("der(der(x))", "x")
    s.eq("der(y)", "y", "x")
    result = s.run()
    assert structural_index(result) == 0
    assert result.eq_to_var == [s.var("der(der(x))"), s.var("der(y)")]


def test_index_two_prescribed_position():
    # der(x) = y, 0 = x - sin(t): y is determined only through the derivative of the constraint.
    s = Structure()
    s.eq("der(x)", "y")
    s.eq("x")
    result = s.run()
    # Only the constraint is differentiated; its derivative takes der(x), pushing y onto eq 0.
    assert result.differentiation_order == [(1, 2)]
    assert result.eq_to_var == [s.var("y"), UNMATCHED, s.var("der(x)")]
    assert structural_index(result) == 2


def test_high_index_chain_and_round_limit():
    # der(x1) = x2, der(x2) = x3, der(x3) = x4, der(x4) = x5, 0 = x1 - f(t): index 5.
    s = Structure()
    for k in range(1, 5):
        s.eq(f"der(x{k})", f"x{k + 1}")
    constraint = s.eq("x1")
    result = s.run()
    assert result.differentiation_counts()[constraint] == 4
    assert structural_index(result) == 5
    with pytest.raises(StructurallySingular) as raised:
        s.run(max_rounds=2)
    assert raised.value.unmatched_eqs == [constraint]


def test_structurally_singular_algebraic_system_names_the_extra_equation():
    # Three equations in two algebraic unknowns.
    s = Structure()
    s.eq("a", "b")
    s.eq("a", "b")
    s.eq("a")
    with pytest.raises(StructurallySingular) as raised:
        s.run()
    assert raised.value.unmatched_eqs == [2]


def test_differentiating_cannot_fix_two_constraints_on_one_state():
    # der(x) = 1, 0 = x - 2, 0 = x - 3: x and der(x) form one unknown family for two equations.
    s = Structure()
    s.eq("der(x)")
    s.eq("x")
    s.eq("x")
    with pytest.raises(StructurallySingular) as raised:
        s.run()
    assert raised.value.unmatched_eqs == [1, 2]


def test_empty_equations_are_left_unmatched():
    s = Structure()
    s.eq("der(x)", "x")
    s.incidence.append([])
    result = s.run()
    assert result.eq_to_var == [s.var("der(x)"), UNMATCHED]
    assert result.differentiation_order == []


def test_long_index_one_chain_scales():
    # z_i = z_{i+1} + x, der(x) = z_0 with the matching found only via long augmenting paths.
    n = 5000
    incidence = [[i, i + 1] for i in range(n - 1)] + [[n - 1, n + 1]] + [[0, n + 1]]
    var_to_diff = [UNMATCHED] * n + [n + 1, UNMATCHED]   # var n is x, n+1 is der(x)
    result = pantelides(len(incidence), n + 2, incidence, var_to_diff)
    assert result.differentiation_order == []
    assert_consistent(result, len(incidence), n + 2, incidence)


@st.composite
def dae_structures(draw):
    """Random DAEs: some variables are states with an explicit derivative variable."""
    n_base = draw(st.integers(1, 7))
    is_state = draw(st.lists(st.booleans(), min_size=n_base, max_size=n_base))
    var_to_diff = [UNMATCHED] * n_base
    for var in range(n_base):
        if is_state[var]:
            var_to_diff[var] = len(var_to_diff)
            var_to_diff.append(UNMATCHED)
    n_vars = len(var_to_diff)
    n_eqs = draw(st.integers(0, n_base + 1))
    incidence = [sorted(draw(st.sets(st.integers(0, n_vars - 1), min_size=1, max_size=3)))
                 for _ in range(n_eqs)]
    return n_eqs, n_vars, incidence, var_to_diff


def family_matching_deficit(n_eqs, incidence, var_to_diff):
    if n_eqs == 0:
        return 0
    family = derivative_families(var_to_diff)
    rows = [eq for eq in range(n_eqs) for var in incidence[eq]]
    cols = [family[var] for eq in range(n_eqs) for var in incidence[eq]]
    matrix = scipy.sparse.csr_matrix((np.ones(len(rows)), (rows, cols)),
                                     shape=(n_eqs, len(var_to_diff)))
    matched = int((maximum_bipartite_matching(matrix, perm_type="column") >= 0).sum())
    return n_eqs - matched


@settings(max_examples=300, deadline=None)
@given(dae_structures())
def test_random_daes_reduce_or_are_reported_singular(structure):
    n_eqs, n_vars, incidence, var_to_diff = structure
    deficit = family_matching_deficit(n_eqs, incidence, var_to_diff)
    if deficit:
        with pytest.raises(StructurallySingular) as raised:
            pantelides(n_eqs, n_vars, incidence, var_to_diff)
        assert len(raised.value.unmatched_eqs) == deficit
        return
    result = pantelides(n_eqs, n_vars, incidence, var_to_diff, max_rounds=n_vars + 2)
    assert_consistent(result, n_eqs, n_vars, incidence)
    for var in range(n_vars):
        if var_to_diff[var] != UNMATCHED:
            assert result.var_to_diff[var] == var_to_diff[var]
    index = structural_index(result)
    deepest = max(result.differentiation_counts(), default=0)
    derivatives = {d for d in result.var_to_diff if d != UNMATCHED}
    has_algebraic = any(var not in derivatives and result.var_to_diff[var] == UNMATCHED
                        for var in result.eq_to_var if var != UNMATCHED)
    assert index == deepest + (1 if has_algebraic else 0)


def test_derivative_families_and_inverse_chain():
    # x=0 -> der(x)=2 -> der(der(x))=3; y=1 has no derivative.
    var_to_diff = [2, UNMATCHED, 3, UNMATCHED]
    assert derivative_families(var_to_diff) == [0, 1, 0, 0]
    assert invert_derivative_chain(var_to_diff) == [UNMATCHED, UNMATCHED, 0, 2]
    with pytest.raises(ValueError):
        derivative_families([1, 0])
