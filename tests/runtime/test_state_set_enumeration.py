"""The compile-time list of state sets (compiler/lower/state_set_enumeration.py) holds every set the
runtime's choice (variants.dummy_choice) makes: checked at random points, wide in magnitude and with
zeros, of the unknowns the levels' Jacobians depend on. The pruning (always_chosen) must never drop
a set pivoting makes; these points would find one it wrongly dropped."""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
import sympy

from compiler import api
from compiler.lower.selection_layout import selection_assignments, selection_levels, selection_metadata
from compiler.lower.state_set_enumeration import always_chosen, possible_choices
from compiler.lower.state_set_variants import _priority_function
from compiler.runtime.variants import dummy_choice
from tests.hard.cartesian_chain import dyad_source

ROOT = Path(__file__).resolve().parents[1]


def compile_quietly(spec: str, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")                # over the variant limit: said elsewhere
        return api.compile(spec, **options)


def chain(tmp_path, n: int):
    path = tmp_path / f"CartesianChain{n}.dyad"
    path.write_text(dyad_source(n, [0.5] * n))
    return compile_quietly(str(path))


def runtime_choices(compilation, points: int, seed: int = 0) -> set:
    """The choices dummy_choice makes at `points` random points (parameters at their defaults)."""
    system = compilation.analysis.system
    levels = selection_levels(system, _priority_function(compilation.analysis))
    layout = selection_metadata(system, levels, [])["levels"]
    entries = selection_assignments(system, levels)
    defaults = {sympy.Symbol(p.name): p.value for p in compilation.flat.parameters if p.value is not None}
    expressions = [sympy.sympify(a.expr).xreplace(defaults) for a in entries]
    symbols = sorted(set().union(*(e.free_symbols for e in expressions)), key=str)
    evaluate = sympy.lambdify(symbols, expressions, "numpy")
    rng = np.random.default_rng(seed)
    made = set()
    for k in range(points):
        values = rng.standard_normal(len(symbols))
        if k % 3 == 1:
            values *= 10.0 ** rng.uniform(-3, 3, len(symbols))
        elif k % 3 == 2:
            values[rng.random(len(symbols)) < 0.3] = 0.0
        with np.errstate(all="ignore"):
            outputs = evaluate(*values)
        choice = dummy_choice(layout, {a.target: float(v) for a, v in zip(entries, outputs)})
        if choice is not None:
            made.add(choice)
    return made


def listed(compilation) -> set:
    system = compilation.analysis.system
    levels = selection_levels(system, _priority_function(compilation.analysis))
    return set(possible_choices(compilation.flat, system, levels, tries=10 ** 6))


@pytest.mark.parametrize("name", ["chain2", "chain3", "pendulum", "transistor"])
def test_every_choice_the_runtime_makes_is_listed(tmp_path, name):
    if name.startswith("chain"):
        compilation = chain(tmp_path, int(name[-1]))
    elif name == "pendulum":
        compilation = compile_quietly("Hard.CartesianPendulumLarge", lib_dirs=(str(ROOT / "models"),))
    else:
        compilation = compile_quietly("StructureModels.TransistorAmplifier",
                                      lib_dirs=(str(ROOT / "structure" / "models"),))
    made = runtime_choices(compilation, 1500)
    possible = listed(compilation)
    assert len(made) >= 2                              # the points do reach several sets
    assert made <= possible, sorted(sorted(c) for c in made - possible)


def test_der_der_positions_are_always_chosen_in_a_chain(tmp_path):
    compilation = chain(tmp_path, 3)
    system = compilation.analysis.system
    first = selection_levels(system, _priority_function(compilation.analysis))[0]
    always = {system.names[v] for v in always_chosen(system, first, list(first.order))}
    assert always == {f"der(der({c}{i}))" for c in "xy" for i in (1, 2, 3)}
    # 656 structurally regular sets, of which 196 keep all six: 14 on each of the two levels
    assert len(listed(compilation)) == 196
    assert all(always <= choice for choice in runtime_choices(compilation, 300, seed=1))
