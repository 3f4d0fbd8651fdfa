"""Greedy tearing of one algebraic loop (after Cellier & Kofman, Elmqvist & Otter).

An algebraic loop (a square BLT block) is turned into: a few tear variables (iteration
unknowns), an ordered list of causal assignments (each equation solved explicitly for one
variable), and as many residual equations as tear variables. Greedy rules:
1. While some equation has exactly one unknown left and is solvable for it, make it causal.
   An equation whose single unknown it cannot be solved for, or with none left, is a residual.
2. Otherwise tear the unknown that scores highest on
   (number of equations it would immediately make causal, number of equations it occurs in,
   lowest index); the first term counts remaining equations with exactly two unknowns that
   are solvable for the other one.
3. Afterwards, each tear variable is dropped again if the others alone still let every
   variable be computed (checked by causal propagation, which is exact for a fixed tear set);
   this pass is skipped for blocks too large for its O(tears * entries) cost.
Minimal tearing is NP-hard; this aims for few tear variables in near-linear time.
"""
from __future__ import annotations

import heapq
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass

# Upper bound on (tear variables x block entries) for the tear-dropping pass.
_REFINEMENT_BUDGET = 2_000_000


@dataclass
class TearingResult:
    """Evaluate `causal` in order (eq solved for var, using only tear variables, earlier causal
    variables and variables outside the block), then the residual equations must vanish."""
    tear_vars: list[int]
    residual_eqs: list[int]
    causal: list[tuple[int, int]]


def tear_block(eqs: list[int], vars: list[int], incidence: list[list[int]],
               solvable: Callable[[int, int], bool]) -> TearingResult:
    if len(eqs) != len(vars):
        raise ValueError(f"tear_block needs a square block, got {len(eqs)} equations "
                         f"and {len(vars)} variables")
    return _GreedyTearing(eqs, vars, incidence, solvable).run()


class _GreedyTearing:
    def __init__(self, eqs: list[int], block_vars: list[int], incidence: list[list[int]],
                 solvable: Callable[[int, int], bool]):
        self.eqs = list(eqs)
        self.vars = list(block_vars)
        local_var = {var: local for local, var in enumerate(self.vars)}
        # rows[e]: the block variables (local indices) of the block's e-th equation.
        self.rows = [sorted({local_var[var] for var in incidence[eq] if var in local_var})
                     for eq in self.eqs]
        self.columns: list[list[int]] = [[] for _ in self.vars]
        for local_eq, row in enumerate(self.rows):
            for local in row:
                self.columns[local].append(local_eq)
        self._solvable = solvable
        self._solvable_cache: dict[tuple[int, int], bool] = {}

        self.known = [False] * len(self.vars)
        self.known_count = 0
        self.done = [False] * len(self.eqs)
        self.unknown_count = [len(row) for row in self.rows]
        self.occurrences = [len(column) for column in self.columns]
        self.pair_score = [0] * len(self.vars)
        self.pair_credit: dict[int, list[int]] = {}   # eq -> vars whose pair_score it raised
        self.ready: deque[int] = deque()
        self.heap: list[tuple[int, int, int]] = []

        self.tear_vars: list[int] = []
        self.residual_eqs: list[int] = []
        self.causal: list[tuple[int, int]] = []

    def is_solvable(self, local_eq: int, local_var: int) -> bool:
        key = (local_eq, local_var)
        if key not in self._solvable_cache:
            self._solvable_cache[key] = bool(self._solvable(self.eqs[local_eq], self.vars[local_var]))
        return self._solvable_cache[key]

    def unknowns_of(self, local_eq: int) -> list[int]:
        return [local for local in self.rows[local_eq] if not self.known[local]]

    def push_score(self, local_var: int) -> None:
        heapq.heappush(self.heap, (-self.pair_score[local_var], -self.occurrences[local_var],
                                   local_var))

    def credit_pairs(self, local_eq: int) -> None:
        first, second = self.unknowns_of(local_eq)
        credited = []
        if self.is_solvable(local_eq, second):
            credited.append(first)
        if self.is_solvable(local_eq, first):
            credited.append(second)
        for local in credited:
            self.pair_score[local] += 1
            self.push_score(local)
        self.pair_credit[local_eq] = credited

    def withdraw_pairs(self, local_eq: int) -> None:
        for local in self.pair_credit.pop(local_eq, []):
            self.pair_score[local] -= 1
            if not self.known[local]:
                self.push_score(local)

    def make_residual(self, local_eq: int) -> None:
        self.done[local_eq] = True
        self.residual_eqs.append(self.eqs[local_eq])
        for local in self.unknowns_of(local_eq):
            self.occurrences[local] -= 1
            self.push_score(local)

    def mark_known(self, local_var: int) -> None:
        self.known[local_var] = True
        self.known_count += 1
        for local_eq in self.columns[local_var]:
            if self.done[local_eq]:
                continue
            self.unknown_count[local_eq] -= 1
            remaining = self.unknown_count[local_eq]
            if remaining == 2:
                self.credit_pairs(local_eq)
            elif remaining == 1:
                self.withdraw_pairs(local_eq)
                self.ready.append(local_eq)
            elif remaining == 0:
                self.make_residual(local_eq)

    def drain_ready(self) -> None:
        while self.ready:
            local_eq = self.ready.popleft()
            if self.done[local_eq] or self.unknown_count[local_eq] != 1:
                continue
            (unknown,) = self.unknowns_of(local_eq)
            if not self.is_solvable(local_eq, unknown):
                self.make_residual(local_eq)
                continue
            self.done[local_eq] = True
            self.causal.append((self.eqs[local_eq], self.vars[unknown]))
            self.mark_known(unknown)

    def next_tear(self) -> int:
        while self.heap:
            neg_pairs, neg_occurrences, local = heapq.heappop(self.heap)
            if self.known[local]:
                continue
            if (-neg_pairs, -neg_occurrences) == (self.pair_score[local], self.occurrences[local]):
                return local
        raise AssertionError("tearing: unknown variables left but none scored")

    def run(self) -> TearingResult:
        for local_eq, count in enumerate(self.unknown_count):
            if count == 2:
                self.credit_pairs(local_eq)
            elif count == 1:
                self.ready.append(local_eq)
            elif count == 0:
                self.make_residual(local_eq)
        for local in range(len(self.vars)):
            self.push_score(local)
        while True:
            self.drain_ready()
            if self.known_count == len(self.vars):
                break
            tear = self.next_tear()
            self.tear_vars.append(self.vars[tear])
            self.mark_known(tear)
        entries = sum(len(row) for row in self.rows)
        if self.tear_vars and len(self.tear_vars) * entries <= _REFINEMENT_BUDGET:
            return self.drop_redundant_tears()
        return TearingResult(tear_vars=self.tear_vars, residual_eqs=self.residual_eqs,
                             causal=self.causal)

    def propagate(self, local_tears: list[int]) -> tuple[list[int], list[tuple[int, int]]] | None:
        """Causalize with a fixed tear set: (residual local eqs, causal local pairs), or None if
        some variable stays undetermined. The known set only grows, so the order of
        assignments cannot change whether propagation succeeds."""
        known = [False] * len(self.vars)
        unknown_count = [len(row) for row in self.rows]
        done = [False] * len(self.eqs)
        residual: list[int] = []
        causal: list[tuple[int, int]] = []
        ready = deque(local_eq for local_eq, count in enumerate(unknown_count) if count <= 1)
        pending_vars = deque(local_tears)
        known_count = 0
        while True:
            while pending_vars:
                local_var = pending_vars.popleft()
                if known[local_var]:
                    continue
                known[local_var] = True
                known_count += 1
                for local_eq in self.columns[local_var]:
                    unknown_count[local_eq] -= 1
                    if unknown_count[local_eq] <= 1 and not done[local_eq]:
                        ready.append(local_eq)
            if not ready:
                break
            local_eq = ready.popleft()
            if done[local_eq]:
                continue
            unknowns = [local for local in self.rows[local_eq] if not known[local]]
            if len(unknowns) == 1 and self.is_solvable(local_eq, unknowns[0]):
                done[local_eq] = True
                causal.append((local_eq, unknowns[0]))
                pending_vars.append(unknowns[0])
            elif not unknowns:
                done[local_eq] = True
                residual.append(local_eq)
        if known_count < len(self.vars):
            return None
        residual.extend(local_eq for local_eq in range(len(self.eqs)) if not done[local_eq])
        return residual, causal

    def drop_redundant_tears(self) -> TearingResult:
        local_var = {var: local for local, var in enumerate(self.vars)}
        tears = [local_var[var] for var in self.tear_vars]
        outcome = self.propagate(tears)
        for candidate in list(reversed(tears)):
            remaining = [local for local in tears if local != candidate]
            attempt = self.propagate(remaining)
            if attempt is not None:
                tears, outcome = remaining, attempt
        assert outcome is not None, "greedy tear set must causalize the block"
        residual, causal = outcome
        return TearingResult(tear_vars=[self.vars[local] for local in tears],
                             residual_eqs=[self.eqs[local_eq] for local_eq in residual],
                             causal=[(self.eqs[e], self.vars[v]) for e, v in causal])
