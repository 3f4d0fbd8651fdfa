"""Every state set a run of a model can switch to, derived at compile time and carried by the
compiled model (`CompiledModel.variants`), so that generated modules and C code switch as the
in-process run does, with the runtime only (compiler/runtime/variants.py).

The runtime's choice at a switch point (variants.dummy_choice, the compiler's dummy-derivative
selection made again, with alias rows folded: state_set_folds.py) takes, level by level, a set of
columns whose block is regular there. Which sets a point can give is not known in advance, so
every set whose folded block is structurally regular is a possible choice, less what pivoting
provably never gives: the columns of leading priority classes it always takes whole (constant
Jacobian, or independent at every point). The sets' product over the levels (each level's
candidates follow from the choice one level up) is the list of variants: 2 for a pendulum, 14
for a 3-body Cartesian chain, (3^N + 1) / 2 for N bodies. Each one is built once (reduce with the
choice forced, then build_variant); beyond VARIANT_LIMIT the model carries none, with a warning,
and the in-process run builds the state sets it reaches lazily (state_set_variants.Switcher).
"""
from __future__ import annotations

import dataclasses
import itertools
import warnings
from typing import Iterator

import numpy as np
import sympy

from compiler.errors import DyadError
from compiler.lower.selection_layout import SelectionLevel, selection_levels
from compiler.lower.state_set_folds import alias_folds, plain_number, unfolded
from compiler.lower.regular_subsets import regular_subsets
from compiler.lower.state_set_variants import Variant, _priority_function, build_variant, forcing, row_positions
from compiler.model.flat import FlatSystem
from compiler.runtime import pivoted_columns
from compiler.structure.differentiate import partial
from compiler.structure.indexed import IndexedSystem
from compiler.structure.reduce import Analysis, StructureReport, reduce

VARIANT_LIMIT = 64
_TRIES = 5_000           # subsets looked at before giving up (most are singular in a long chain)
_COUNT_LIMIT = 1_000       # how far an over-the-limit model's variants are counted (100,000 took 6 s)


class VariantLimitWarning(UserWarning):
    """A model has more possible state sets than are compiled ahead of time."""


class TooManyToList(Exception):
    """The possible state sets were not all found within the subsets looked at."""


def possible_choices(flat: FlatSystem, system: IndexedSystem, levels: list[SelectionLevel],
                     tries: int = _TRIES) -> Iterator[frozenset[str]]:
    """Every dummy-derivative set (names) the runtime's choice can make: on each level, folded
    (state_set_folds.py: every u taken, the choice made without the alias rows and w columns), the
    columns that pivoting takes from the leading priority classes whose Jacobian is constant
    (computed here, at the parameters' defaults), completed by every set of later columns that
    makes the folded block structurally regular; the next level's candidates follow from the
    columns that propagate (variants.propagating). Raises TooManyToList after looking at `tries`
    subsets."""
    constant = _constant_entries(flat, system)
    budget = [tries]

    def spend(looked_at: int) -> None:
        budget[0] -= looked_at
        if budget[0] < 0:
            raise TooManyToList

    folds_of = [alias_folds(system, level.rows, level.order, level.priority.get) for level in levels]

    def walk(k: int, candidates: set[int], dummies: tuple[int, ...]):
        if k == len(levels):
            yield frozenset(system.names[v] for v in dummies)
            return
        level = levels[k]
        folds = [(i, u, w) for i, u, w in folds_of[k] if u in candidates and w in candidates]
        partner = {u: w for _, u, w in folds}
        rows = [e for i, e in enumerate(level.rows) if i not in {i for i, _, _ in folds}]
        order = [v for v in level.order if v in candidates and v not in partner.values()]
        folded = dataclasses.replace(level, rows=tuple(rows))
        fixed, rest = _constant_prefix_choice(system, folded, order, constant)
        fixed, rest = _independent_classes(system, folded, fixed, rest)
        for subset in regular_subsets(row_positions(system, rows), fixed, rest, len(rows) - len(fixed), spend):
            chosen = unfolded(fixed + list(subset), folds)
            taken = set(chosen)
            following = {level.next[v] for v in chosen if v in level.next and
                         (v not in partner or partner[v] in taken)}
            yield from walk(k + 1, following, dummies + tuple(chosen))
    if levels:
        yield from walk(0, set(levels[0].order), ())


def _constant_entries(flat: FlatSystem, system: IndexedSystem):
    """(equation, unknown) -> the value of d equation / d unknown where it does not depend on the
    unknowns (at the parameters' defaults), else None; memoized."""
    values = {sympy.Symbol(p.name): p.value for p in flat.parameters if p.value is not None}
    memo: dict[tuple[int, int], float | None] = {}

    def entry(e: int, v: int) -> float | None:
        if (e, v) not in memo:
            derivative = partial(system.equations[e], system.symbols[v]).xreplace(values)
            try:
                memo[e, v] = float(derivative) if not derivative.free_symbols else None
            except (TypeError, ValueError):
                memo[e, v] = None                  # not a finite number here: as if it varied
            if memo[e, v] is not None and not np.isfinite(memo[e, v]):
                memo[e, v] = None
        return memo[e, v]
    return entry


def _constant_prefix_choice(system: IndexedSystem, level: SelectionLevel, order: list[int], constant):
    """The columns pivoting takes from the leading priority classes of `order` whose entries are all
    constant (the same at every point), and the columns after those classes."""
    classes: list[list[int]] = []
    for j, v in enumerate(order):
        if j == 0 or level.priority[v] != level.priority[order[j - 1]]:
            classes.append([])
        classes[-1].append(j)
    matrix = np.zeros((len(level.rows), len(order)))
    prefix: list[list[int]] = []
    for members in classes:
        entries = [(i, j, constant(e, order[j]) if order[j] in system.incidence[e] else 0.0)
                   for j in members for i, e in enumerate(level.rows)]
        if any(value is None for _, _, value in entries):
            break
        for i, j, value in entries:
            matrix[i, j] = value
        prefix.append(members)
    if not prefix:
        return [], order
    end = prefix[-1][-1] + 1
    picked = pivoted_columns(matrix[:, :end], prefix, len(level.rows))
    return [order[j] for j in sorted(picked)], order[end:]


def _independent_classes(system: IndexedSystem, level: SelectionLevel, fixed: list[int], rest: list[int]):
    """`fixed` and `rest` with the leading priority classes of `rest` that pivoting takes whole
    moved to `fixed`: a class that fits in the rows left and whose columns, with `fixed`, are
    independent at every point and parameter value (_triangular). Pivoting then finds a part
    orthogonal to the columns taken in every column of the class (the threshold, 1e-8 of the
    largest entry, aside) and takes them all."""
    fixed, rest = list(fixed), list(rest)
    while rest:
        members = [v for v in rest if level.priority[v] == level.priority[rest[0]]]
        if len(fixed) + len(members) > len(level.rows) or \
                not _triangular(system, level.rows, fixed + members):
            break
        fixed, rest = fixed + members, rest[len(members):]
    return fixed, rest


def _triangular(system: IndexedSystem, rows, columns) -> bool:
    """Whether `columns` peel off one by one, each on a row of its own among the columns left where
    its entry is a non-zero number: their block on those rows is then triangular with that
    number on the diagonal, its determinant never zero."""
    left, free_rows = set(columns), list(rows)
    while left:
        for v in sorted(left):
            row = next((e for e in free_rows if v in system.incidence[e]
                        and not any(u in system.incidence[e] for u in left if u != v)
                        and plain_number(system, e, v)), None)
            if row is not None:
                left.discard(v)
                free_rows.remove(row)
                break
        else:
            return False
    return True


def with_variants(flat: FlatSystem, analysis: Analysis, root: Variant,
                  limit: int = VARIANT_LIMIT) -> Variant:
    """`root` whose model carries every other possible state set (`model.variants`), or `root`
    unchanged, with a VariantLimitWarning, when there are more than `limit`."""
    system = analysis.system
    levels = selection_levels(system, _priority_function(analysis))
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
            # counted by going on with the same walk (walking again from the start, as before,
            # looked at the first choices' subsets twice: 0.1 s at a 32-body chain)
            count = len(choices) + sum(1 for _ in itertools.islice(walk, _COUNT_LIMIT + 1 - len(choices)))
            counted = f"more than {_COUNT_LIMIT:,}" if count > _COUNT_LIMIT else f"{count:,}"
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
            # selection_layout following: kept under what it is, the runtime never picks it wrongly
            variants.setdefault(got, built.model)
    return dataclasses.replace(root, model=root.model.replace(variants=variants))
