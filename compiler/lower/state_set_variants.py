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
from compiler.lower.state_set_levels import _priority_function, monitored_levels
from compiler.lower.regular_subsets import augment_path
from compiler.lower.to_casadi import lower
from compiler.runtime.variants import DUMMIES, SELECTION, dummy_choice
from compiler.model.collection import fewer_collections
from compiler.structure.differentiate import partial
from compiler.structure.indexed import IndexedSystem
from compiler.structure.reduce import Analysis, StructureReport, reduce
from compiler.structure.reduced import Assignment, ReducedSystem


# the output every structurally zero entry of a monitored level's Jacobian reads (at chain N = 32,
# 1,920 of its 2,048 entries, each its own output before: 2,780 -> 861 outputs per state set)
PIVOT_ZERO = "__pivot_zero"


@dataclass
class Variant:
    states: tuple[str, ...]
    reduced: ReducedSystem
    model: runtime.CompiledModel
    report: StructureReport
    public_names: list[str]
    # every state set reached from this one, built once and kept for later runs (shared by all)
    siblings: dict = field(default_factory=dict)


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
        entries = []                # per entry of the level's Jacobian, row-major: its pivot output
        for i, e in enumerate(rows):
            occurring = set(system.incidence[e])
            for j, v in enumerate(candidates):
                derivative = partial(system.equations[e], system.symbols[v]) if v in occurring else 0
                if derivative == 0:
                    entries.append(None)            # structurally zero: one shared zero output
                else:
                    entries.append(len(pivots))
                    pivots.append(Assignment(f"__pivot{level}[{i},{j}]", derivative))
        layouts.append((rows, candidates, chosen, entries))
    if any(None in entries for *_, entries in layouts):
        pivots.append(Assignment(PIVOT_ZERO, sympy.Integer(0)))
    # every level's Jacobian over all its possible candidates: the runtime makes the choice again
    priority = _priority_function(analysis)
    levels = selection_levels(system, priority)
    selecting = selection_assignments(system, levels)
    monitored = dataclasses.replace(reduced, observables=list(reduced.observables) + pivots + selecting,
                                    output_names=public + internal + [a.target for a in pivots + selecting])
    model = lower(monitored)
    offset = len(public) + len(internal)
    dummies = sorted(system.names[v] for _, _, chosen in report.levels for v in chosen)
    zero = offset + len(pivots) - 1
    model = model.replace(state_sets=[_state_set(rows, cands, chosen,
                                                 [zero if k is None else offset + k for k in entries],
                                                 system.names, priority)
                                      for rows, cands, chosen, entries in layouts],
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


def _state_set(rows: list[int], candidates: list[int], chosen: list[int], entries: list[int],
               names: list[str], priority) -> dict:
    """A monitored level in the runtime's plain form (CompiledModel.state_sets): the level's
    Jacobian entries are the outputs `entries` (row-major; every structural zero is the one output
    PIVOT_ZERO), candidate positions are grouped by priority class, lowest first, as the
    dummy-derivative choice orders them."""
    order = sorted(range(len(candidates)), key=lambda j: (priority(candidates[j]), j))
    classes: dict[int, list[int]] = {}
    for j in order:
        classes.setdefault(priority(candidates[j]), []).append(j)
    return {"rows": len(rows), "candidates": [names[v] for v in candidates],
            "chosen": [candidates.index(v) for v in chosen], "classes": list(classes.values()),
            "entries": list(entries)}


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
            with fewer_collections():     # as while compiling: a full collection of the compiler's
                variant = self._build(dummies, values)      # heap took 0.08 s of a 0.9 s run
            variant.siblings = cache
            cache[variant.states] = variant
        if self.c_code and variant.model.native_library is None:
            from compiler.cache.c_code import compile_c
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


def row_positions(system: IndexedSystem, rows) -> dict[int, list[int]]:
    """Every unknown of `rows` -> the positions of the rows that contain it, in row order."""
    positions: dict[int, list[int]] = {}
    for i, e in enumerate(rows):
        for v in system.incidence[e]:
            positions.setdefault(v, []).append(i)
    return positions


def matching(system: IndexedSystem, rows, columns, positions: dict[int, list[int]] | None = None) -> dict[int, int]:
    """A maximum matching column -> row position (augmenting paths; levels are small).
    `positions`: row_positions(system, rows), given where many column sets share the rows (a scan
    of every row per column was 1.5 of 2 s of the state-set enumeration at chain N = 32)."""
    if positions is None:
        positions = row_positions(system, rows)
    row_to_column: dict[int, int] = {}
    for v in columns:
        augment_path(positions, row_to_column, v, set())
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
