"""Strongly connected components (Tarjan) and block lower triangular ordering."""
from __future__ import annotations

from compiler.structure.graph.matching import UNMATCHED


def strongly_connected_components(n: int, successors: list[list[int]]) -> list[list[int]]:
    """Tarjan's algorithm, iterative. Nodes are 0..n-1; each component is sorted ascending.

    Order: reverse topological. If some edge leads from component A to a different component B,
    then B comes before A. With edges "u needs v", the list is therefore a valid evaluation
    order. Roots are tried in increasing node order, so the result is deterministic.
    """
    unvisited = -1
    index_of = [unvisited] * n
    lowlink = [0] * n
    on_stack = [False] * n
    stack: list[int] = []
    components: list[list[int]] = []
    next_index = 0
    for root in range(n):
        if index_of[root] != unvisited:
            continue
        index_of[root] = lowlink[root] = next_index
        next_index += 1
        stack.append(root)
        on_stack[root] = True
        call_stack = [(root, 0)]
        while call_stack:
            node, cursor = call_stack[-1]
            children = successors[node]
            descended = False
            while cursor < len(children):
                child = children[cursor]
                cursor += 1
                if index_of[child] == unvisited:
                    call_stack[-1] = (node, cursor)
                    index_of[child] = lowlink[child] = next_index
                    next_index += 1
                    stack.append(child)
                    on_stack[child] = True
                    call_stack.append((child, 0))
                    descended = True
                    break
                if on_stack[child] and index_of[child] < lowlink[node]:
                    lowlink[node] = index_of[child]
            if descended:
                continue
            call_stack.pop()
            if call_stack:
                parent = call_stack[-1][0]
                if lowlink[node] < lowlink[parent]:
                    lowlink[parent] = lowlink[node]
            if lowlink[node] == index_of[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack[member] = False
                    component.append(member)
                    if member == node:
                        break
                component.sort()
                components.append(component)
    return components


def block_lower_triangular(n_eqs: int, incidence: list[list[int]], eq_to_var: list[int]
                           ) -> list[tuple[list[int], list[int]]]:
    """Blocks (equations, variables) in solve order for a system where every equation is matched.

    Block k's equations use only its own variables, variables of earlier blocks, and variables
    no equation is matched to (those are treated as known inputs, e.g. states). Within a block,
    equations are ascending and variables[i] is the one matched to equations[i].
    """
    unmatched = [eq for eq in range(n_eqs) if eq_to_var[eq] == UNMATCHED]
    if unmatched:
        raise ValueError(f"block_lower_triangular needs every equation matched; "
                         f"unmatched: {unmatched[:10]}")
    var_to_eq: dict[int, int] = {var: eq for eq, var in enumerate(eq_to_var[:n_eqs])}
    needs: list[list[int]] = []
    for eq in range(n_eqs):
        own = eq_to_var[eq]
        needs.append([var_to_eq[var] for var in incidence[eq]
                      if var != own and var in var_to_eq])
    return [(component, [eq_to_var[eq] for eq in component])
            for component in strongly_connected_components(n_eqs, needs)]
