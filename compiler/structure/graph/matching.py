"""Bipartite matching between equations and variables (integer structures only).

Equations and variables are 0-based ints; `incidence[eq]` lists the variables of `eq`.
A matching is a pair of lists `eq_to_var` / `var_to_eq` with -1 meaning "unmatched".
All traversals are iterative (no recursion limit) and visit neighbours in list order, so the
result depends only on the input lists, never on hashing.
"""
from __future__ import annotations

from collections import deque

UNMATCHED = -1


def _allowed_or_all(n_vars: int, var_allowed: list[bool] | None) -> list[bool]:
    return [True] * n_vars if var_allowed is None else var_allowed


def _greedy_initial_matching(eqs_in_order: list[int], incidence: list[list[int]],
                             allowed: list[bool], var_weight: list[int] | None,
                             eq_to_var: list[int], var_to_eq: list[int]) -> None:
    """Cheap start for Hopcroft–Karp; with weights it is also where the preference is expressed.

    Each equation takes its free allowed variable of highest weight (ties: first in its incidence
    list). Hopcroft–Karp then only re-routes what the greedy pass could not match, so most
    equations keep their preferred variable; the weights are a preference, not a guarantee.
    """
    for eq in eqs_in_order:
        best = UNMATCHED
        for var in incidence[eq]:
            if not allowed[var] or var_to_eq[var] != UNMATCHED:
                continue
            if var_weight is None:
                best = var
                break
            if best == UNMATCHED or var_weight[var] > var_weight[best]:
                best = var
        if best != UNMATCHED:
            eq_to_var[eq] = best
            var_to_eq[best] = eq


def maximum_matching(n_eqs: int, n_vars: int, incidence: list[list[int]], *,
                     var_allowed: list[bool] | None = None, eq_order: list[int] | None = None,
                     var_weight: list[int] | None = None) -> tuple[list[int], list[int]]:
    """Maximum cardinality matching (Hopcroft–Karp, O(E sqrt(V))).

    `var_allowed[v] == False` excludes variable v. `eq_order` is the order in which equations are
    considered; it influences which of several maximum matchings is returned, and equations
    it leaves out stay unmatched (a maximum matching of the listed ones). `var_weight`:
    a greedy initial pass matches each equation to its free variable of highest weight before the
    augmenting phases; see `_greedy_initial_matching`.
    Returns (eq_to_var, var_to_eq), -1 for unmatched.
    """
    allowed = _allowed_or_all(n_vars, var_allowed)
    order = list(range(n_eqs)) if eq_order is None else list(eq_order)
    eq_to_var = [UNMATCHED] * n_eqs
    var_to_eq = [UNMATCHED] * n_vars
    _greedy_initial_matching(order, incidence, allowed, var_weight, eq_to_var, var_to_eq)

    infinity = n_eqs + 1
    dist = [infinity] * n_eqs
    while True:
        # BFS: layer the equations by alternating distance from the free equations.
        queue: deque[int] = deque()
        for eq in order:
            if eq_to_var[eq] == UNMATCHED:
                dist[eq] = 0
                queue.append(eq)
            else:
                dist[eq] = infinity
        free_var_distance = infinity
        while queue:
            eq = queue.popleft()
            if dist[eq] >= free_var_distance:
                continue
            for var in incidence[eq]:
                if not allowed[var]:
                    continue
                mate = var_to_eq[var]
                if mate == UNMATCHED:
                    if free_var_distance == infinity:
                        free_var_distance = dist[eq] + 1
                elif dist[mate] == infinity:
                    dist[mate] = dist[eq] + 1
                    queue.append(mate)
        if free_var_distance == infinity:
            break
        # DFS along the layers: vertex-disjoint shortest augmenting paths, iteratively.
        next_edge = [0] * n_eqs
        for root in order:
            if eq_to_var[root] != UNMATCHED:
                continue
            _augment_along_layers(root, incidence, allowed, eq_to_var, var_to_eq, dist,
                                  next_edge, free_var_distance, infinity)
    return eq_to_var, var_to_eq


def _augment_along_layers(root: int, incidence: list[list[int]], allowed: list[bool],
                          eq_to_var: list[int], var_to_eq: list[int], dist: list[int],
                          next_edge: list[int], free_var_distance: int, infinity: int) -> bool:
    path_eqs = [root]
    path_vars: list[int] = []
    while path_eqs:
        eq = path_eqs[-1]
        neighbours = incidence[eq]
        advanced = False
        while next_edge[eq] < len(neighbours):
            var = neighbours[next_edge[eq]]
            next_edge[eq] += 1
            if not allowed[var]:
                continue
            mate = var_to_eq[var]
            if mate == UNMATCHED:
                if dist[eq] + 1 != free_var_distance:
                    continue
                path_vars.append(var)
                for path_eq, path_var in zip(path_eqs, path_vars):
                    eq_to_var[path_eq] = path_var
                    var_to_eq[path_var] = path_eq
                return True
            if dist[mate] == dist[eq] + 1:
                path_vars.append(var)
                path_eqs.append(mate)
                advanced = True
                break
        if not advanced:
            # Dead end: never revisit this equation in this phase.
            dist[eq] = infinity
            path_eqs.pop()
            if path_vars:
                path_vars.pop()
    return False


class _AllAllowed:
    def __getitem__(self, var: int) -> bool:
        return True


_ALL_ALLOWED = _AllAllowed()


def augmenting_path(eq: int, incidence: list[list[int]], eq_to_var: list[int],
                    var_to_eq: list[int], var_allowed: list[bool] | None = None
                    ) -> tuple[bool, list[int], list[int]]:
    """Single-source augmenting path search from equation `eq` (MC21-style DFS, as in Pantelides).

    Like StateSelection.jl's `construct_augmenting_path!`: at each equation first look for a free
    allowed variable, otherwise descend through the allowed variables not visited yet.
    Returns (found, visited_eqs, visited_vars) in visiting order; on success the matching lists are
    updated in place. On failure, visited_vars is every allowed variable of every visited
    equation and visited_eqs their matched equations plus `eq` (the set Pantelides
    differentiates). Precondition: `eq` is unmatched.
    """
    if eq_to_var[eq] != UNMATCHED:
        raise ValueError(f"augmenting_path: equation {eq} is already matched")
    # Pantelides calls this once per unmatched equation and the alternating paths of a long
    # chain run through O(N) equations: the loop below is the inner loop of index reduction.
    allowed = _ALL_ALLOWED if var_allowed is None else var_allowed
    visited_eqs = [eq]
    visited_vars: list[int] = []
    seen_vars: set[int] = set()
    path_eqs = [eq]
    path_vars: list[int] = []
    cursors = [0]
    while path_eqs:
        neighbours = incidence[path_eqs[-1]]
        cursor = cursors[-1]
        if cursor == 0:
            for var in neighbours:
                if var_to_eq[var] == UNMATCHED and allowed[var]:
                    path_vars.append(var)
                    for path_eq, path_var in zip(path_eqs, path_vars):
                        eq_to_var[path_eq] = path_var
                        var_to_eq[path_var] = path_eq
                    if var not in seen_vars:
                        seen_vars.add(var)
                        visited_vars.append(var)
                    return True, visited_eqs, visited_vars
        size = len(neighbours)
        while cursor < size:
            var = neighbours[cursor]
            cursor += 1
            if var in seen_vars or not allowed[var]:
                continue
            seen_vars.add(var)
            visited_vars.append(var)
            mate = var_to_eq[var]
            visited_eqs.append(mate)
            path_vars.append(var)
            path_eqs.append(mate)
            cursors[-1] = cursor
            cursors.append(0)
            break
        else:
            path_eqs.pop()
            cursors.pop()
            if path_vars:
                path_vars.pop()
    return False, visited_eqs, visited_vars
