"""Worker side of sweeping a model whose state set switches: a StateSetSwitcher over the variants
built before the sweep (compiler/sweep/variants.py), with the runtime only (no sympy).

Where the driver asks for another state set, the choice is made as the compiler makes it: at each
monitored level, pivoting (runtime.pivoted_columns, the routine the compiler's dummy-derivative
selection uses) over that level's Jacobian, which the current variant outputs. The dummy
derivatives that result name the variant to continue in.
"""
from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

from compiler.runtime import CompiledModel, SimulationFailed, pivoted_columns
from compiler.runtime.state_sets import level_matrix


class PrebuiltSwitcher:
    def __init__(self, models: Sequence[CompiledModel], dummies: Sequence[Sequence[str]],
                 public_names: Sequence[str]):
        self.public_names = list(public_names)
        self.first = models[0]
        self._by_dummies = {frozenset(d): m for m, d in zip(models, dummies)}
        self._dummies_of = {id(m): frozenset(d) for m, d in zip(models, dummies)}

    def switch(self, model: CompiledModel, values: Mapping[str, float], t: float) -> CompiledModel:
        dummies = set(self._dummies_of[id(model)])
        column = np.array([values[name] for name in model.output_names], dtype=float)
        for level in model.state_sets:
            rows = int(level["rows"])
            chosen = pivoted_columns(level_matrix(level, column), level["classes"], rows)
            if len(chosen) < rows:
                return model                    # no full choice here: the driver reports it
            dummies -= set(level["candidates"])
            dummies |= {level["candidates"][j] for j in chosen}
        found = self._by_dummies.get(frozenset(dummies))
        if found is None:
            reason = (f"the state set chosen here (dummy derivatives {', '.join(sorted(dummies))}) is "
                      f"none of the {len(self._by_dummies)} built before the sweep")
            raise SimulationFailed(f"simulation of {model.name} stopped at t = {t:.10g}: {reason}", t, reason)
        return found
