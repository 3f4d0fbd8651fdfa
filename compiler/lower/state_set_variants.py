"""Dynamic state selection, compile side: the state-set variants of a model, lowered to CasADi.

A variant is the model compiled for one choice of dummy derivatives. Besides the user's signals
it outputs every unknown of the index-1 system (so that any other variant can start from its
values) and, for each level of the dummy-derivative choice whose pivot block depends on the
unknowns, the entries of that level's Jacobian (the runtime watches them, see
compiler/runtime/state_sets.py). A choice whose pivot blocks are constant is valid everywhere: it
is never monitored. Which state sets exist and which levels are watched is structural analysis
(compiler/structure/state_selection/); the runtime's one driver integrates and switches
(compiler/runtime/variants.py).
"""
from __future__ import annotations

import dataclasses
import itertools
import warnings
from dataclasses import dataclass


from compiler import runtime
from compiler.errors import DyadError
from compiler.model.flat import FlatSystem
from compiler.lower.to_casadi import lower
from compiler.runtime.selection_rules import watched_level
from compiler.runtime.variants import DUMMIES, SELECTION
from compiler.structure.reduce import Analysis, StructureReport, reduce
from compiler.structure.reduced import ReducedSystem
from compiler.structure.state_selection.enumeration import TooManyToList, possible_choices
from compiler.structure.state_selection.forcing import forcing
from compiler.structure.state_selection.layout import (choice_priority, selection_assignments, selection_levels,
                                                       selection_metadata)
from compiler.structure.state_selection.monitored import monitored_levels, pivot_outputs

VARIANT_LIMIT = 64
COUNT_LIMIT = 1_000      # how far an over-the-limit model's variants are counted (100,000 took 6 s)


class VariantLimitWarning(UserWarning):
    """A model has more possible state sets than are compiled ahead of time."""


@dataclass
class Variant:
    states: tuple[str, ...]
    reduced: ReducedSystem
    model: runtime.CompiledModel
    report: StructureReport
    public_names: list[str]


def build_variant(flat: FlatSystem, analysis: Analysis, point: dict[str, float] | None,
                  reduced: ReducedSystem | None = None, report: StructureReport | None = None) -> Variant:
    if reduced is None:
        report = StructureReport()
        reduced = reduce(flat, point=point, report=report, analysis=analysis)
    system = analysis.system
    public = list(reduced.output_names)
    known = set(public)
    internal = [n for n in system.names if n not in known]
    watched = monitored_levels(flat, analysis, report)
    pivots, layouts = pivot_outputs(system, watched)
    # every level's Jacobian over all its possible candidates: the runtime makes the choice again
    priority = choice_priority(analysis)
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
                                      for (_, rows, cands, chosen), entries in zip(watched, layouts)],
                          metadata={**model.metadata, DUMMIES: dummies,
                                    SELECTION: selection_metadata(system, levels, public)})
    return Variant(tuple(monitored.states), monitored, model, report, public)


def _state_set(rows: list[int], candidates: list[int], chosen: list[int], entries: list[int],
               names: list[str], priority) -> dict:
    """A monitored level in the runtime's plain form (selection_rules.watched_level): the level's
    Jacobian entries are the outputs `entries` (row-major; every structural zero is the one output
    PIVOT_ZERO)."""
    return watched_level(len(rows), [names[v] for v in candidates], [candidates.index(v) for v in chosen],
                         [priority(v) for v in candidates], entries)


def with_variants(flat: FlatSystem, analysis: Analysis, root: Variant,
                  limit: int = VARIANT_LIMIT) -> Variant:
    """`root` whose model carries every other possible state set (`model.variants`), or `root`
    unchanged, with a VariantLimitWarning, when there are more than `limit`."""
    system = analysis.system
    levels = selection_levels(system, choice_priority(analysis))
    walk = possible_choices(flat, system, levels)
    choices: list | None = []
    try:
        choices.extend(itertools.islice(walk, limit + 1))
    except TooManyToList:
        choices = None
    if choices is None or len(choices) > limit:
        try:
            if choices is None:
                raise TooManyToList
            # counted by going on with the same walk (not walking again from the start)
            count = len(choices) + sum(1 for _ in itertools.islice(walk, COUNT_LIMIT + 1 - len(choices)))
            counted = f"more than {COUNT_LIMIT:,}" if count > COUNT_LIMIT else f"{count:,}"
        except TooManyToList:
            counted = f"more than {limit}"
        warnings.warn(f"model {flat.name} has {counted} possible state sets, more than the {limit} "
                      f"compiled with it: a run makes the others from its index-1 system when it "
                      f"reaches them (in-process, from the cache, in generated code and in C alike)",
                      VariantLimitWarning, stacklevel=2)
        return root
    first = frozenset(root.model.metadata["dummy_derivatives"])
    variants = {}
    for dummies in choices:
        if dummies == first:
            continue
        report = StructureReport()
        try:
            reduced = reduce(flat, report=report, analysis=analysis, pivots=forcing(system, dummies))
        except DyadError:
            continue                   # regular level by level, yet no causal order: never chosen
        built = build_variant(flat, analysis, None, reduced=reduced, report=report)
        got = frozenset(built.model.metadata["dummy_derivatives"])
        if got != first:
            # `got` differs from `dummies` only if the selection changed its rules without
            # state_selection/layout.py following: kept under what it is, the runtime never picks it wrongly
            variants.setdefault(got, built.model)
    return dataclasses.replace(root, model=root.model.replace(variants=variants))
