import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from compiler.structure.graph import tear_block
from graph_strategies import nonsingular_square_systems


def always(eq, var):
    return True


def assert_tearing_order(eqs, block_vars, incidence, solvable, result):
    assert len(result.tear_vars) == len(result.residual_eqs)
    assert sorted(result.residual_eqs + [eq for eq, _ in result.causal]) == sorted(eqs)
    assert sorted(result.tear_vars + [var for _, var in result.causal]) == sorted(block_vars)
    block = set(block_vars)
    known = set(result.tear_vars)
    for eq, var in result.causal:
        assert solvable(eq, var)
        assert var in incidence[eq]
        for other in incidence[eq]:
            if other != var and other in block:
                assert other in known, f"eq {eq} solved for {var} before {other} is known"
        known.add(var)


def test_resistor_network_loop_needs_one_tear():
    # U0 = u1 + u2, u1 = R1 i1, u2 = R2 i2, u3 = R3 i3, u2 = u3, i1 = i2 + i3
    i1, i2, i3, u1, u2, u3 = range(6)
    incidence = [[u1, u2], [i1, u1], [i2, u2], [i3, u3], [u2, u3], [i1, i2, i3]]
    eqs, block_vars = list(range(6)), list(range(6))
    result = tear_block(eqs, block_vars, incidence, always)
    assert len(result.tear_vars) == 1
    assert_tearing_order(eqs, block_vars, incidence, always, result)


def test_dense_linear_block_tears_all_but_one():
    n = 6
    incidence = [list(range(n)) for _ in range(n)]
    result = tear_block(list(range(n)), list(range(n)), incidence, always)
    assert len(result.tear_vars) == n - 1
    assert len(result.causal) == 1
    assert_tearing_order(list(range(n)), list(range(n)), incidence, always, result)


def test_block_without_solvable_pairs_is_all_torn():
    incidence = [[0, 1], [1, 2], [0, 2]]
    never = lambda eq, var: False  # noqa: E731
    result = tear_block([0, 1, 2], [0, 1, 2], incidence, never)
    assert result.causal == []
    assert sorted(result.tear_vars) == [0, 1, 2]
    assert sorted(result.residual_eqs) == [0, 1, 2]


def test_triangular_block_is_fully_causal_in_dependency_order():
    incidence = [[0, 1, 2], [1], [1, 2]]
    result = tear_block([0, 1, 2], [0, 1, 2], incidence, always)
    assert result.tear_vars == []
    assert result.causal == [(1, 1), (2, 2), (0, 0)]


def test_unsolvable_pair_chooses_another_equation_for_the_variable():
    # eq0 = sin(a) + b (solvable only for b), eq1 = a + b: solve eq1 for a after tearing b? No:
    # tear a, then eq0 gives b explicitly and eq1 is the residual — or the reverse.
    incidence = [[0, 1], [0, 1]]
    solvable = lambda eq, var: not (eq == 0 and var == 0)  # noqa: E731
    result = tear_block([0, 1], [0, 1], incidence, solvable)
    assert len(result.tear_vars) == 1
    assert_tearing_order([0, 1], [0, 1], incidence, solvable, result)


def test_variables_outside_the_block_are_known():
    # Block {eq1, eq2} x {v1, v2}; v0 (solved earlier) appears in both.
    incidence = [[0], [0, 1, 2], [0, 2]]
    result = tear_block([1, 2], [1, 2], incidence, always)
    assert result.tear_vars == []
    assert result.causal == [(2, 2), (1, 1)]


def test_non_square_block_is_rejected():
    with pytest.raises(ValueError):
        tear_block([0], [0, 1], [[0, 1]], always)


def solve_by_tearing(result, coefficients, rhs, n):
    """Evaluate the torn linear system: causal assignments, then Newton on the tear residuals
    (one step is exact for a linear system)."""
    def evaluate(tear_values):
        x = np.zeros(n)
        x[result.tear_vars] = tear_values
        for eq, var in result.causal:
            row = coefficients[eq]
            x[var] = (rhs[eq] - (row @ x - row[var] * x[var])) / row[var]
        return x, np.array([coefficients[eq] @ x - rhs[eq] for eq in result.residual_eqs])

    tears = len(result.tear_vars)
    if tears == 0:
        return evaluate(np.zeros(0))[0]
    _, base = evaluate(np.zeros(tears))
    jacobian = np.column_stack([evaluate(np.eye(tears)[k])[1] - base for k in range(tears)])
    return evaluate(np.linalg.solve(jacobian, -base))[0]


@settings(max_examples=200, deadline=None)
@given(nonsingular_square_systems(max_size=10), st.integers(0, 2**32 - 1), st.data())
def test_torn_linear_systems_reproduce_the_direct_solution(system, seed, data):
    n, incidence = system
    rng = np.random.default_rng(seed)
    coefficients = np.zeros((n, n))
    for eq, row in enumerate(incidence):
        coefficients[eq, row] = rng.uniform(0.5, 2.0, len(row)) * rng.choice([-1, 1], len(row))
    if np.linalg.cond(coefficients) > 1e8:
        return
    not_solvable = data.draw(st.sets(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)),
                                     max_size=n))
    solvable = lambda eq, var: (eq, var) not in not_solvable  # noqa: E731
    result = tear_block(list(range(n)), list(range(n)), incidence, solvable)
    assert_tearing_order(list(range(n)), list(range(n)), incidence, solvable, result)
    rhs = rng.normal(size=n)
    x = solve_by_tearing(result, coefficients, rhs, n)
    np.testing.assert_allclose(coefficients @ x, rhs, atol=1e-6 * max(1.0, np.abs(x).max()))


def fewest_tears_by_brute_force(n, incidence, solvable):
    import itertools

    def determines_everything(tears):
        known = set(tears)
        progress = True
        while progress:
            progress = False
            for eq in range(n):
                unknown = [var for var in incidence[eq] if var not in known]
                if len(unknown) == 1 and solvable(eq, unknown[0]):
                    known.add(unknown[0])
                    progress = True
        return len(known) == n

    return next(size for size in range(n + 1)
                if any(determines_everything(t) for t in itertools.combinations(range(n), size)))


def test_tear_count_is_near_optimal_on_small_random_blocks():
    rng = np.random.default_rng(20240601)
    excess = []
    for _ in range(400):
        n = int(rng.integers(2, 7))
        hidden = rng.permutation(n)
        incidence = [sorted(set(rng.choice(n, int(rng.integers(0, 4)), replace=True).tolist())
                            | {int(hidden[eq])}) for eq in range(n)]
        bad = {(int(rng.integers(n)), int(rng.integers(n))) for _ in range(int(rng.integers(0, n)))}
        solvable = lambda eq, var, bad=bad: (eq, var) not in bad  # noqa: E731
        result = tear_block(list(range(n)), list(range(n)), incidence, solvable)
        excess.append(len(result.tear_vars) - fewest_tears_by_brute_force(n, incidence, solvable))
    assert min(excess) == 0
    assert max(excess) <= 1
    assert sum(excess) <= 0.03 * len(excess)
