"""Switching among the state-set variants a compiled model carries (`CompiledModel.variants`).

Every state set a run can reach is derived once, at compile time
(compiler/structure/state_selection/enumeration.py), and travels with the model; where the current
set degrades, the run continues in the variant whose dummy derivatives the numerical choice selects
at that point. The choice is the compiler's own dummy-derivative selection made again here, with
the runtime only (the rules both use are in selection_rules.py):

Level by level, from the most-differentiated constraints down, pivoting (`pivoted_columns`) over the
level's Jacobian with respect to its candidate derivatives picks as many columns as the level has
rows; the candidates of the next level are the undifferentiated versions of the columns picked.
Each variant outputs the entries of every level's Jacobian over all candidates any choice can offer
(`selection_output` names them), and its metadata holds the levels' layout (`SELECTION`) and its own
dummy derivatives (`DUMMIES`). So a generated module, a sweep worker and the in-process run pick the
same variant at the same point.
"""
from __future__ import annotations

from functools import lru_cache
from typing import Mapping, Sequence

import numpy as np

from .errors import SimulationFailed
from .model import CompiledModel
from .selection_rules import level_choice, next_candidates, present_folds

SELECTION = "state_selection"        # metadata: {"public": [...], "levels": [...]}, see dummy_choice
DUMMIES = "dummy_derivatives"        # metadata: this variant's dummy derivatives (sorted names)


def selection_output(level: int, row: int, candidate: str) -> str:
    """The output holding d(row-th constraint of `level`) / d(candidate)."""
    return f"__select{level}[{row},{candidate}]"


def dummy_choice(levels: Sequence[Mapping], values: Mapping[str, float]) -> frozenset[str] | None:
    """The dummy derivatives the compiler's numerical selection takes at the point `values` (all
    outputs of a variant there), or None where some level has no regular choice.

    A level is {"rows": n, "order": candidate names in the compiler's order of preference,
    "priority": {name: state priority}, "next": {name: its candidate on the next level}, "folds":
    [[row, u, w], ...] its alias rows (compiler/structure/state_selection/folds.py; a fold counts
    where u and w are both candidates)}; the first level's candidates are all of its `order`. An
    entry without an output is structurally zero."""
    candidates = set(levels[0]["order"]) if levels else set()
    dummies: list[str] = []
    given = _selection_entries(values)
    for k, level in enumerate(levels):
        rows = int(level["rows"])
        order = [c for c in level["order"] if c in candidates]
        entries = [[0.0] * len(order) for _ in range(rows)]      # one array made at the end
        column = {name: j for j, name in enumerate(order)}
        for i, name, value in given.get(k, ()):
            j = column.get(name)
            if j is not None and i < rows:
                entries[i][j] = float(value)
        matrix = np.array(entries, dtype=float).reshape(rows, len(order))
        folds = level_folds(level, order)
        picked = level_choice(matrix, [level["priority"][name] for name in order], rows,
                              folds=[(int(r), column[u], column[w]) for r, u, w in folds])
        if len(picked) < rows:
            return None
        chosen = [order[j] for j in picked]
        dummies.extend(chosen)
        candidates = next_candidates(chosen, {u: w for _, u, w in folds}, level["next"])
    return frozenset(dummies)


def level_folds(level: Mapping, order: Sequence[str]) -> list[tuple]:
    """The alias folds (row, u, w) of a selection level that count among the candidates `order`."""
    return present_folds(level.get("folds", ()), order)


def _selection_entries(values: Mapping[str, float]) -> dict[int, list[tuple[int, str, float]]]:
    """level -> (row, candidate, value) of every selection output among `values` (named by
    selection_output). Read from the names present, not looked up by every name a level could
    have: a 32-body chain's first level has 96 rows x 128 candidates, of which 288 occur."""
    found: dict[int, list[tuple[int, str, float]]] = {}
    for key, level, row, candidate in _selection_layout(tuple(values)):
        found.setdefault(level, []).append((row, candidate, values[key]))
    return found


@lru_cache(maxsize=64)
def _selection_layout(names: tuple[str, ...]) -> tuple[tuple[str, int, int, str], ...]:
    """(name, level, row, candidate) of the selection outputs among `names`, parsed once per
    variant's output names (a run asks at every switch)."""
    layout = []
    for key in names:
        if key.startswith("__select") and key.endswith("]"):
            level, _, rest = key[len("__select"):].partition("[")
            row, _, candidate = rest[:-1].partition(",")
            if level.isdigit() and row.isdigit():
                layout.append((key, int(level), int(row), candidate))
    return tuple(layout)


def variant_models(model: CompiledModel) -> dict[frozenset, CompiledModel]:
    """Every state set of `model` by its dummy derivatives, `model` itself included."""
    found = dict(model.variants)
    found[frozenset(model.metadata.get(DUMMIES, ()))] = model
    return found


class VariantSwitcher:
    """The runtime's StateSetSwitcher for a model that carries its variants: at the switch point,
    the variant of the dummy derivatives `dummy_choice` selects. `fallback` (another
    StateSetSwitcher) is asked for a choice that is none of the variants, which can happen only
    where a parameter value changed a choice the compiler took as constant; without one the run
    stops there with SimulationFailed."""

    def __init__(self, model: CompiledModel, fallback=None):
        selection = model.metadata.get(SELECTION)
        if not model.variants or selection is None:
            raise ValueError(f"model {model.name} carries no state-set variants")
        self.public_names = list(selection["public"])
        self.levels = selection["levels"]
        self.fallback = fallback
        self._by_dummies = variant_models(model)

    def switch(self, model: CompiledModel, values: Mapping[str, float], t: float) -> CompiledModel:
        dummies = dummy_choice(self.levels, values)
        if dummies is None:
            return model                      # no regular choice here: the driver reports it
        found = self._by_dummies.get(dummies)
        if found is not None:
            return found
        if self.fallback is not None:
            return self.fallback.switch(model, values, t)
        reason = (f"the state set chosen here (dummy derivatives {', '.join(sorted(dummies))}) is none "
                  f"of the {len(self._by_dummies)} compiled with the model")
        raise SimulationFailed(f"simulation of {model.name} stopped at t = {t:.10g}: {reason}", t, reason)


def variant_label(dummies: frozenset) -> str:
    """A stable text for a set of dummy derivatives (sorted names, comma-separated)."""
    return ",".join(sorted(dummies))


def on_native_libraries(model: CompiledModel, own: str | None, by_label: Mapping[str, str]) -> CompiledModel:
    """`model` on its C library `own` and each state-set variant on `by_label[variant_label(its
    dummy derivatives)]` (None where a library is not given): how a model that travels without its
    libraries (a sweep payload, a generated module) is put back on them."""
    return model.with_native_library(own).replace(variants={
        dummies: variant.with_native_library(by_label.get(variant_label(dummies)))
        for dummies, variant in model.variants.items()})
