"""Which levels of a model's dummy-derivative choice a run must watch (compiler/lower/
state_set_variants.py builds the variants that watch them): the levels of the choice as the
runtime's choice sees them (alias rows folded, state_set_folds.py), and of those the ones whose
chosen pivot block depends on the unknowns.

What does not depend on the choice (the state priorities, the equations that tie a dummy to a kept
state) is derived once per analysed system and shared by every variant built from it.
"""
from __future__ import annotations

import weakref

import sympy

from compiler.lower.selection_layout import selection_levels
from compiler.lower.state_set_folds import alias_folds
from compiler.model.flat import FlatSystem
from compiler.structure.dummy_derivatives import base_variable
from compiler.structure.differentiate import partial
from compiler.structure.reduce import Analysis, StructureReport

def monitored_levels(flat: FlatSystem, analysis: Analysis, report: StructureReport) -> list[tuple]:
    """Levels of the dummy-derivative choice that can degrade: more candidates than rows and a
    chosen pivot block that depends on the unknowns. Each as (level, rows, candidates, chosen)."""
    system = analysis.system
    constant = set(sympy.Symbol(p.name) for p in flat.parameters)
    priority = _priority_function(analysis)
    levels = []
    for level, (rows, candidates, chosen) in enumerate(folded_levels(analysis, report)):
        if len(candidates) <= len(rows):
            continue
        kept = [v for v in candidates if v not in chosen]
        stand_ins = _stand_ins(system, kept)
        candidates_of_interest = set(chosen) - stand_ins
        varying_set = set()
        for e in rows:                                 # only where the unknown occurs: linear in size
            for v in system.incidence[e]:
                if v in candidates_of_interest and v not in varying_set and \
                        not partial(system.equations[e], system.symbols[v]).free_symbols <= constant:
                    varying_set.add(v)
        varying = [v for v in chosen if v in varying_set]
        if not varying:
            continue                                   # a constant pivot block is valid everywhere
        if min(priority(v) for v in kept) > max(priority(v) for v in varying):
            continue                                   # only a hinted state could take over: keep the hint
        levels.append((level, rows, candidates, chosen))
    return levels


def folded_levels(analysis: Analysis, report: StructureReport) -> list[tuple[list, list, list]]:
    """The levels of the choice `report` holds as the runtime's choice sees them
    (variants.dummy_choice): without the alias rows and their w columns (state_set_folds.py), the
    folded choice (the u whose w is chosen, and the other chosen columns), and each level's
    candidates only the next versions of the columns that propagate (variants.propagating), with
    the chosen ones added (a choice made without folding, by the compiler at the start, may hold
    others: a switch then always leaves it)."""
    system = analysis.system
    layout = selection_levels(system, _priority_function(analysis))
    out, candidates = [], None
    for k, (rows, all_candidates, chosen) in enumerate(report.levels):
        if candidates is None:
            candidates = list(all_candidates)
        allowed = set(candidates) | set(chosen)
        candidates = [v for v in all_candidates if v in allowed]
        folds = fold_table(system, layout[k], rows, candidates) if k < len(layout) else []
        partner = {u: w for _, u, w in folds}
        fold_rows = {i for i, _, _ in folds}
        taken = set(chosen)
        folded_chosen = [v for v in chosen if v not in partner.values() and
                         (v not in partner or partner[v] in taken)]
        out.append(([e for i, e in enumerate(rows) if i not in fold_rows],
                    [v for v in candidates if v not in partner.values()], folded_chosen))
        following = {layout[k].next[v] for v in chosen if v in layout[k].next and
                     (v not in partner or partner[v] in taken)} if k < len(layout) else set()
        candidates = list(following)
    return out


def fold_table(system, level, rows: list[int], candidates: list[int]) -> list[tuple[int, int, int]]:
    """The folds of selection level `level` that count among `candidates` (both columns there)."""
    if list(level.rows) != list(rows):
        return []                             # the layout does not mirror the choice: no folding
    present = set(candidates)
    return [(i, u, w) for i, u, w in alias_folds(system, level.rows, level.order, level.priority.get)
            if u in present and w in present]


def _stand_ins(system, kept: list[int]) -> set[int]:
    """Dummies that only stand in for a kept state: der(der(phi)) when `w = der(phi)` holds and
    der(w) is kept. Exchanging the two changes nothing, so they never call for a switch."""
    kept_set = set(kept)
    return {ddphi for dw, ddphi in _per_system(system, "stand-in pairs", _stand_in_pairs) if dw in kept_set}


def stand_in_pairs(system) -> list[tuple[int, int]]:
    """The system's (der(w), der(der(phi))) pairs (see _stand_in_pairs), found once per system."""
    return _per_system(system, "stand-in pairs", _stand_in_pairs)


def _stand_in_pairs(system) -> list[tuple[int, int]]:
    """(der(w), der(der(phi))) for every equation that says w = +-der(phi) (unit coefficients):
    a scan of every equation, 3 ms at chain N = 32, once per system instead of once per variant."""
    diff_to_var = system.diff_to_var()
    pairs = []
    for residual in system.equations:
        symbols = [s for s in residual.free_symbols if s in system.index_of]
        if len(symbols) != 2:
            continue
        a, b = (system.index_of[s] for s in symbols)
        for w, dphi in ((a, b), (b, a)):
            if diff_to_var[dphi] >= 0 and abs(partial(residual, system.symbols[w])) == 1 \
                    and abs(partial(residual, system.symbols[dphi])) == 1:
                dw, ddphi = system.var_to_diff[w], system.var_to_diff[dphi]
                if ddphi >= 0:
                    pairs.append((dw, ddphi))
    return pairs


_DERIVED: dict[int, tuple[weakref.ref, dict]] = {}


def _per_system(system, key: str, build):
    """build(system), computed once per system object (kept while the system lives)."""
    found = _DERIVED.get(id(system))
    if found is None or found[0]() is not system:
        found = (weakref.ref(system, lambda _, at=id(system): _DERIVED.pop(at, None)), {})
        _DERIVED[id(system)] = found
    if key not in found[1]:
        found[1][key] = build(system)
    return found[1][key]


def _priority_function(analysis: Analysis):
    """The state priority of a candidate as the run-time choice and the list of state sets order
    it: twice the declared priority of its base variable, less one where the model never
    differentiates that variable (der(g) only appears in equations the index reduction
    differentiated, g = f(y) say): between equal declared priorities its derivative is rather a
    dummy, and the variables the model differentiates stay states. The compiler's first choice
    orders by the declared priority alone."""
    system = analysis.system
    diff_to_var = system.diff_to_var()
    diff_to_eq = system.diff_to_eq()
    differentiated = {diff_to_var[d] for e in range(system.n_eqs) if diff_to_eq[e] < 0
                      for d in system.incidence[e] if diff_to_var[d] >= 0}

    def priority(v: int) -> int:
        base = base_variable(system, v, diff_to_var)
        declared = analysis.priorities.get(system.names[base], 0)
        return 2 * declared - (0 if base in differentiated else 1)
    return priority


