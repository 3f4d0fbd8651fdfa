"""Dynamic state selection, compile side: the state-set variants of a model and the switcher the
runtime calls where the current set degrades.

A variant is the model compiled for one choice of dummy derivatives. Besides the user's signals
it outputs every unknown of the index-1 system (so that any other variant can start from its
values) and, for each level of the dummy-derivative choice whose pivot block depends on the
unknowns, the entries of that level's Jacobian (the runtime watches them, see
compiler/runtime/state_sets.py). A choice whose pivot blocks are constant is valid everywhere: it
is never monitored. The runtime's one driver integrates; this module only provides variants.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np
import sympy

from compiler import runtime
from compiler.errors import DyadError
from compiler.model.flat import FlatSystem
from compiler.lower.selection_layout import selection_assignments, selection_levels, selection_metadata
from compiler.lower.state_set_folds import alias_folds
from compiler.lower.to_casadi import lower
from compiler.runtime.variants import DUMMIES, SELECTION, dummy_choice
from compiler.structure.dummy_derivatives import base_variable
from compiler.structure.differentiate import partial
from compiler.structure.indexed import IndexedSystem
from compiler.structure.reduce import Analysis, StructureReport, reduce
from compiler.structure.reduced import Assignment, ReducedSystem


@dataclass
class Variant:
    states: tuple[str, ...]
    reduced: ReducedSystem
    model: runtime.CompiledModel
    report: StructureReport
    public_names: list[str]
    # every state set reached from this one, built once and kept for later runs (shared by all)
    siblings: dict = field(default_factory=dict)


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
    diff_to_var = system.diff_to_var()
    stand_ins = set()
    for residual in system.equations:
        symbols = [s for s in residual.free_symbols if s in system.index_of]
        if len(symbols) != 2:
            continue
        a, b = (system.index_of[s] for s in symbols)
        for w, dphi in ((a, b), (b, a)):
            if diff_to_var[dphi] >= 0 and abs(partial(residual, system.symbols[w])) == 1 \
                    and abs(partial(residual, system.symbols[dphi])) == 1:
                dw, ddphi = system.var_to_diff[w], system.var_to_diff[dphi]
                if dw in kept_set and ddphi >= 0:
                    stand_ins.add(ddphi)
    return stand_ins


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


def build_variant(flat: FlatSystem, analysis: Analysis, point: dict[str, float] | None,
                  reduced: ReducedSystem | None = None, report: StructureReport | None = None) -> Variant:
    if reduced is None:
        report = StructureReport()
        reduced = reduce(flat, point=point, report=report, analysis=analysis)
    system = analysis.system
    public = list(reduced.output_names)
    known = set(public)
    internal = [n for n in system.names if n not in known]
    pivots: list[Assignment] = []
    layouts = []
    for level, rows, candidates, chosen in monitored_levels(flat, analysis, report):
        start = len(pivots)
        for i, e in enumerate(rows):
            for j, v in enumerate(candidates):
                pivots.append(Assignment(f"__pivot{level}[{i},{j}]",
                                         partial(system.equations[e], system.symbols[v])))
        layouts.append((rows, candidates, chosen, start))
    # every level's Jacobian over all its possible candidates: the runtime makes the choice again
    priority = _priority_function(analysis)
    levels = selection_levels(system, priority)
    selecting = selection_assignments(system, levels)
    monitored = dataclasses.replace(reduced, observables=list(reduced.observables) + pivots + selecting,
                                    output_names=public + internal + [a.target for a in pivots + selecting])
    model = lower(monitored)
    offset = len(public) + len(internal)
    dummies = sorted(system.names[v] for _, _, chosen in report.levels for v in chosen)
    model = model.replace(state_sets=[_state_set(rows, cands, chosen, offset + start, system.names,
                                                 priority)
                                      for rows, cands, chosen, start in layouts],
                          metadata={**model.metadata, DUMMIES: dummies,
                                    SELECTION: _with_folds(system, levels, selection_metadata(system, levels, public))})
    return Variant(tuple(monitored.states), monitored, model, report, public)


def _with_folds(system, levels, layout: dict) -> dict:
    """The runtime's layout with each level's alias folds as [row, u, w] (names)."""
    names = system.names
    return {**layout, "levels": [
        {**plain, "folds": [[i, names[u], names[w]]
                            for i, u, w in alias_folds(system, level.rows, level.order, level.priority.get)]}
        for plain, level in zip(layout["levels"], levels)]}


def _state_set(rows: list[int], candidates: list[int], chosen: list[int], first_output: int,
               names: list[str], priority) -> dict:
    """A monitored level in the runtime's plain form (CompiledModel.state_sets): the level's
    Jacobian entries are outputs first_output... (row-major), candidate positions are grouped by
    priority class, lowest first, as the dummy-derivative choice orders them."""
    order = sorted(range(len(candidates)), key=lambda j: (priority(candidates[j]), j))
    classes: dict[int, list[int]] = {}
    for j in order:
        classes.setdefault(priority(candidates[j]), []).append(j)
    return {"rows": len(rows), "candidates": [names[v] for v in candidates],
            "chosen": [candidates.index(v) for v in chosen], "classes": list(classes.values()),
            "entries": list(range(first_output, first_output + len(rows) * len(candidates)))}


class Switcher:
    """The runtime's StateSetSwitcher for a model that carries no variants (over the limit of
    state_set_enumeration): where the current state set degrades, make the run-time choice
    (variants.dummy_choice, as VariantSwitcher does) and hand back its variant, built then and
    kept. A run that began in C code stays in C code in every state set."""

    def __init__(self, flat: FlatSystem, analysis: Analysis, first: Variant,
                 model: runtime.CompiledModel | None = None):
        """`model`: the first state set's model as the run has it (compiled to C, say)."""
        self.flat, self.analysis, self.first = flat, analysis, first
        self.public_names = list(first.public_names)
        model = first.model if model is None else model
        self.c_code = model.native_library is not None
        known = first.siblings.get(first.states)
        if known is None or (self.c_code and known.model.native_library is None):
            first.siblings[first.states] = dataclasses.replace(first, model=model)

    def switch(self, model: runtime.CompiledModel, values: Mapping[str, float], t: float) -> runtime.CompiledModel:
        layout = model.metadata.get(SELECTION)
        dummies = dummy_choice(layout["levels"], values) if layout else None
        if layout and dummies is None:
            return model                      # no regular choice here: the driver reports it
        cache = self.first.siblings
        variant = next((known for known in cache.values()
                        if frozenset(known.model.metadata.get(DUMMIES, ())) == dummies), None)
        if variant is None:
            variant = self._build(dummies, values)
            variant.siblings = cache
            cache[variant.states] = variant
        if self.c_code and variant.model.native_library is None:
            from compiler.lower.ccodegen import compile_c
            variant.model = compile_c(variant.model)
        return variant.model

    def _build(self, dummies: frozenset | None, values: Mapping[str, float]) -> Variant:
        """The variant of the run-time choice `dummies` (variants.dummy_choice, as the variants a
        model carries are chosen), or, for a model without the layout, of the compiler's choice."""
        if dummies is not None:
            report = StructureReport()
            try:
                reduced = reduce(self.flat, report=report, analysis=self.analysis,
                                 pivots=forcing(self.analysis.system, dummies))
                return build_variant(self.flat, self.analysis, None, reduced=reduced, report=report)
            except DyadError:
                pass                          # no causal order for that choice: the compiler's own
        point = {k: float(v) for k, v in values.items() if not k.startswith("__pivot")}
        return build_variant(self.flat, self.analysis, point)


def matching(system: IndexedSystem, rows, columns) -> dict[int, int]:
    """A maximum matching column -> row position (augmenting paths; levels are small)."""
    column_rows = {v: [i for i, e in enumerate(rows) if v in system.incidence[e]] for v in columns}
    row_to_column: dict[int, int] = {}

    def augment(v, seen) -> bool:
        for i in column_rows[v]:
            if i not in seen:
                seen.add(i)
                if i not in row_to_column or augment(row_to_column[i], seen):
                    row_to_column[i] = v
                    return True
        return False
    for v in columns:
        augment(v, set())
    return {v: i for i, v in row_to_column.items()}


def forcing(system: IndexedSystem, dummies: frozenset[str]):
    """A Jacobian (rows, cols) -> matrix under which the numerical selection picks `dummies`:
    a unit entry per chosen column on the row it is matched to, zero elsewhere."""
    def jacobian(rows: list[int], cols: list[int]) -> np.ndarray:
        chosen = [v for v in cols if system.names[v] in dummies]
        matrix = np.zeros((len(rows), len(cols)))
        for v, i in matching(system, rows, chosen).items():
            matrix[i, cols.index(v)] = 1.0
        return matrix
    return jacobian
