"""Client side of sweeping a model whose state set switches: build its state-set variants here.

`dyadc simulate` builds the variant it switches to during the run, with the compiler
(compiler/lower/state_set_variants.py: sympy). A sweep worker has no compiler, so every variant
a run could switch to is built here, once, and shipped with the model; the worker's switcher
(compiler/sweep/switching.py) only picks among them.

Which variants: those of every dummy-derivative choice at the monitored levels. A choice is
forced by giving the base variables of the monitored candidates state priorities in a chosen
order (the dummy-derivative selection takes the lowest first) and selecting at the model's start
point, as the compile did, so that the levels nobody monitors keep the choice the compile made
there (structurally, where the start point leaves a forced column at zero). Every order of those
base variables is tried; distinct choices are built once each. A variant is the compiler's own
build_variant of that choice, so it is the model the compile-side switcher would build.
"""
from __future__ import annotations

import dataclasses
import itertools
import math

from compiler.errors import DyadError

MAX_ORDERS = 5040              # 7 base variables at the monitored levels
LOW = -10 ** 6                 # below any declared state priority


@dataclasses.dataclass(frozen=True)
class PrebuiltVariants:
    """Every state set of a model: `dummies[i]` are the dummy derivatives of `models[i]`; the first
    is the compiled model itself. `public_names` are the signals every variant reports."""
    models: tuple
    dummies: tuple[tuple[str, ...], ...]
    public_names: tuple[str, ...]


def prebuild_variants(compilation) -> PrebuiltVariants:
    from compiler.lower.state_set_variants import build_variant
    from compiler.structure.dummy_derivatives import base_variable
    from compiler.structure.reduce import StructureReport, reduce, select_states

    flat, analysis = compilation.flat, compilation.analysis
    system = analysis.system
    diff_to_var = system.diff_to_var()
    index = {name: i for i, name in enumerate(system.names)}
    bases = sorted({system.names[base_variable(system, index[c], diff_to_var)]
                    for level in compilation.model.state_sets for c in level["candidates"]})
    if math.factorial(len(bases)) > MAX_ORDERS:
        raise DyadError(f"cannot sweep {compilation.model.name}: its state set switches among "
                        f"{len(bases)} variables ({', '.join(bases)}), too many to build every state "
                        "set before the sweep", hint="simulate its cases one by one with `dyadc simulate -p`")
    start = flat.initial_values()
    first = frozenset(compilation.report.dummy_derivatives)
    choices: dict[frozenset, tuple] = {first: None}
    for order in itertools.permutations(bases):
        priorities = {**analysis.priorities, **{b: LOW + rank for rank, b in enumerate(order)}}
        for point in (start, None):
            try:
                selection = select_states(system, priorities, flat, point)
            except DyadError:
                continue                           # this order gives no valid choice
            key = frozenset(system.names[v] for v in selection.dummies)
            choices.setdefault(key, (priorities, point))
    models, dummies = [compilation.model], [tuple(sorted(first))]
    for key, how in choices.items():
        if how is None:
            continue
        priorities, point = how
        report = StructureReport()
        forced = dataclasses.replace(analysis, priorities=priorities)
        try:
            reduced = reduce(flat, point=point, report=report, analysis=forced)
            variant = build_variant(flat, analysis, None, reduced=reduced, report=report)
        except DyadError:
            continue                               # structurally singular with these states
        models.append(variant.model)
        dummies.append(tuple(sorted(key)))
    return PrebuiltVariants(tuple(models), tuple(dummies), tuple(compilation.variant.public_names))
