"""Which levels of a model's dummy-derivative choice a run must watch (compiler/lower/
state_set_variants.py builds the variants that watch them): the levels of the choice as the
runtime's choice sees them (alias rows folded, folds.py), and of those the ones that
runtime.selection_rules.may_degrade says can degrade, which the runtime asks too for the state
sets it makes from the universal system (runtime/universal.py).

What does not depend on the choice (the equations that tie a dummy to a kept state) is derived
once per analysed system and shared by every variant built from it.
"""
from __future__ import annotations

import weakref
from typing import TYPE_CHECKING

import sympy

from compiler.runtime.selection_rules import folded_level, may_degrade, next_candidates, present_folds
from compiler.structure.differentiate import partial
from compiler.structure.reduced import Assignment
from compiler.structure.state_selection.folds import alias_folds, common_factor_ratio
from compiler.structure.state_selection.layout import choice_priority, selection_levels

if TYPE_CHECKING:
    from compiler.model.flat import FlatSystem
    from compiler.structure.reduce import Analysis, StructureReport

# the output every structurally zero entry of a monitored level's Jacobian reads (at chain N = 32,
# 1,920 of its 2,048 entries)
PIVOT_ZERO = "__pivot_zero"


def monitored_levels(flat: FlatSystem, analysis: Analysis, report: StructureReport) -> list[tuple]:
    """Levels of the dummy-derivative choice that can degrade: more candidates than rows and a
    chosen pivot block that depends on the unknowns. Each as (level, rows, candidates, chosen)."""
    system = analysis.system
    constant = set(sympy.Symbol(p.name) for p in flat.parameters)
    priority = choice_priority(analysis)
    pairs = stand_in_pairs(system)
    levels = []
    for level, (rows, candidates, chosen) in enumerate(folded_levels(analysis, report)):
        rows_of: dict[int, list[int]] = {}
        for e in rows:
            for v in system.incidence[e]:
                rows_of.setdefault(v, []).append(e)

        def varies(v: int) -> bool:
            return any(not partial(system.equations[e], system.symbols[v]).free_symbols <= constant
                       for e in rows_of.get(v, ()))

        if may_degrade(len(rows), candidates, chosen, {v: priority(v) for v in candidates}, pairs, varies):
            levels.append((level, rows, candidates, chosen))
    return levels


def pivot_outputs(system, monitored: list[tuple]) -> tuple[list[Assignment], list[list[int | None]]]:
    """The outputs that hold the Jacobians of the `monitored` levels (monitored_levels): one per
    structurally non-zero entry, and PIVOT_ZERO last where some entry is zero; and per level its
    entries (row-major) as positions in those outputs, None for a zero entry (PIVOT_ZERO)."""
    pivots: list[Assignment] = []
    layouts = []
    for level, rows, candidates, _ in monitored:
        entries: list[int | None] = []
        for i, e in enumerate(rows):
            occurring = set(system.incidence[e])
            for j, v in enumerate(candidates):
                derivative = partial(system.equations[e], system.symbols[v]) if v in occurring else 0
                if derivative == 0:
                    entries.append(None)            # structurally zero: one shared zero output
                else:
                    entries.append(len(pivots))
                    pivots.append(Assignment(f"__pivot{level}[{i},{j}]", derivative))
        layouts.append(entries)
    if any(None in entries for entries in layouts):
        pivots.append(Assignment(PIVOT_ZERO, sympy.Integer(0)))
    return pivots, layouts


def folded_levels(analysis: Analysis, report: StructureReport) -> list[tuple[list, list, list]]:
    """The levels of the choice `report` holds as the runtime's choice sees them
    (variants.dummy_choice): folded (selection_rules.folded_level), and each level's candidates
    only the next versions of the columns that propagate (selection_rules.next_candidates), with
    the chosen ones added (a choice made without folding, by the compiler at the start, may hold
    others: a switch then always leaves it)."""
    system = analysis.system
    layout = selection_levels(system, choice_priority(analysis))
    out, candidates = [], None
    for k, (rows, all_candidates, chosen) in enumerate(report.levels):
        if candidates is None:
            candidates = list(all_candidates)
        allowed = set(candidates) | set(chosen)
        candidates = [v for v in all_candidates if v in allowed]
        folds = fold_table(system, layout[k], rows, candidates) if k < len(layout) else []
        folded = folded_level(list(range(len(rows))), candidates, chosen, folds)
        out.append(([rows[i] for i in folded.rows], folded.candidates, folded.chosen))
        candidates = list(next_candidates(chosen, {u: w for _, u, w in folds}, layout[k].next)) \
            if k < len(layout) else []
    return out


def fold_table(system, level, rows: list[int], candidates: list[int]) -> list[tuple[int, int, int]]:
    """The folds of selection level `level` that count among `candidates` (both columns there)."""
    if list(level.rows) != list(rows):
        return []                             # the layout does not mirror the choice: no folding
    return present_folds(alias_folds(system, level.rows, level.order, level.priority.get), candidates)


def stand_in_pairs(system) -> list[tuple[int, int]]:
    """The system's (der(w), der(der(phi))) pairs (see _stand_in_pairs), found once per system."""
    return _per_system(system, "stand-in pairs", _stand_in_pairs)


def _stand_in_pairs(system) -> list[tuple[int, int]]:
    """(der(w), der(der(phi))) for every equation that says w = +-der(phi) (unit coefficients, up to
    a factor of parameters that scales the equation: folds.common_factor_ratio):
    a scan of every equation, once per system instead of once per variant."""
    diff_to_var = system.diff_to_var()
    pairs = []
    for residual in system.equations:
        symbols = [s for s in residual.free_symbols if s in system.index_of]
        if len(symbols) != 2:
            continue
        a, b = (system.index_of[s] for s in symbols)
        for w, dphi in ((a, b), (b, a)):
            ratio = common_factor_ratio(system, residual, w, dphi) if diff_to_var[dphi] >= 0 else None
            if ratio is not None and abs(ratio) == 1:
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
