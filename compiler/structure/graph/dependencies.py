"""Reachability in a directed graph (used to prune what no state or output depends on)."""
from __future__ import annotations


def reachable(n: int, successors: list[list[int]], roots: list[int]) -> list[bool]:
    """reached[v] is True iff v is a root or lies on a path from one (iterative DFS)."""
    reached = [False] * n
    pending: list[int] = []
    for root in roots:
        if not reached[root]:
            reached[root] = True
            pending.append(root)
    while pending:
        node = pending.pop()
        for successor in successors[node]:
            if not reached[successor]:
                reached[successor] = True
                pending.append(successor)
    return reached
