from hypothesis import given, settings
from hypothesis import strategies as st

from compiler.structure.graph import reachable
from graph_strategies import digraphs


def test_reachability_follows_edges_only_forward():
    successors = [[1], [2], [], [0]]
    assert reachable(4, successors, [1]) == [False, True, True, False]
    assert reachable(4, successors, [3]) == [True, True, True, True]
    assert reachable(4, successors, []) == [False] * 4


def test_long_chain():
    n = 100000
    successors = [[i + 1] for i in range(n - 1)] + [[]]
    assert all(reachable(n, successors, [0]))


@settings(max_examples=200, deadline=None)
@given(digraphs(), st.data())
def test_reached_set_is_the_closure_of_the_roots(graph, data):
    n, successors = graph
    if n == 0:
        return
    roots = data.draw(st.lists(st.integers(0, n - 1), max_size=3))
    reached = reachable(n, successors, roots)
    for root in roots:
        assert reached[root]
    for node in range(n):
        if reached[node]:
            assert all(reached[successor] for successor in successors[node])
    # Minimal: every reached node has a path from a root (fixpoint iteration as the oracle).
    closure = set(roots)
    while True:
        grown = closure | {s for node in closure for s in successors[node]}
        if grown == closure:
            break
        closure = grown
    assert {node for node in range(n) if reached[node]} == closure
