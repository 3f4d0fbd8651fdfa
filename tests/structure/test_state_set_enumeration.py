"""The compile-time list of state sets (compiler/structure/state_selection/enumeration.py) holds every set the
runtime's choice (variants.dummy_choice) makes: checked at random points, wide in magnitude and with
zeros, of the unknowns the levels' Jacobians depend on. The list leaves out what the folded choice
(state_selection/folds.py) and whole priority classes taken never give; these points would find a set
it wrongly left out."""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
import sympy

from compiler import api
from compiler.structure.state_selection.enumeration import possible_choices
from compiler.structure.state_selection.folds import alias_folds
from compiler.structure.state_selection.layout import choice_priority, selection_assignments, selection_levels
from compiler.runtime import pivoted_columns
from compiler.runtime.variants import DUMMIES, SELECTION, dummy_choice
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
    """The choices dummy_choice makes at `points` random points (parameters at their defaults)
    with the selection layout the compiled model carries."""
    system = compilation.analysis.system
    levels = selection_levels(system, choice_priority(compilation.analysis))
    layout = compilation.model.metadata[SELECTION]["levels"]          # as the model carries it
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
    levels = selection_levels(system, choice_priority(compilation.analysis))
    return set(possible_choices(compilation.flat, system, levels, tries=10 ** 6))


MODELS = {"pendulum": ("Hard.CartesianPendulumLarge", ROOT / "models"),
          "slider_crank": ("Hard.SliderCrank", ROOT / "models"),
          "four_bar": ("StructureModels.FourBar", ROOT / "structure" / "models"),
          "transistor": ("StructureModels.TransistorAmplifier", ROOT / "structure" / "models")}


@pytest.mark.parametrize("name, count", [("chain2", 5), ("chain3", 14), ("pendulum", 2), ("slider_crank", 6), ("four_bar", 8),
                                         ("transistor", 39)])
def test_every_choice_the_runtime_makes_is_listed(tmp_path, name, count):
    if name.startswith("chain"):
        compilation = chain(tmp_path, int(name[-1]))
    else:
        spec, folder = MODELS[name]
        compilation = compile_quietly(spec, lib_dirs=(str(folder),))
    made = runtime_choices(compilation, 1500)
    possible = listed(compilation)
    assert len(possible) == count
    assert len(made) >= 2                              # the points do reach several sets
    assert made <= possible, sorted(sorted(c) for c in made - possible)


def test_a_chain_folds_its_alias_rows_and_keeps_positions_and_velocities_together(tmp_path):
    compilation = chain(tmp_path, 3)
    system = compilation.analysis.system
    first = selection_levels(system, choice_priority(compilation.analysis))[0]
    folds = alias_folds(system, first.rows, first.order, first.priority.get)
    assert {(system.names[u], system.names[w]) for _, u, w in folds} == \
        {(f"der(der({c}{i}))", f"der(v{c}{i})") for c in "xy" for i in (1, 2, 3)}
    for choice in runtime_choices(compilation, 300, seed=1):
        for c in "xy":
            for i in (1, 2, 3):     # the position is a dummy exactly where the velocity is
                assert (f"der({c}{i})" in choice) == (f"der(v{c}{i})" in choice)


def test_folded_pivoting_takes_u_always_and_w_with_u():
    # rows: alias row of column 0 (u) and 2 (w), then one constraint row over columns 0 and 1
    matrix = np.array([[1.0, 0.0, -1.0],
                       [0.3, 2.0, 0.0]])
    classes = [[0, 1, 2]]
    assert sorted(pivoted_columns(matrix, classes, 2, folds=[(0, 0, 2)])) == [0, 1]   # 2.0 > 0.3
    matrix[1] = [3.0, 2.0, 0.0]
    assert sorted(pivoted_columns(matrix, classes, 2, folds=[(0, 0, 2)])) == [0, 2]   # w with u
    matrix[1] = [0.0, 0.0, 0.0]
    assert len(pivoted_columns(matrix, classes, 2, folds=[(0, 0, 2)])) < 2           # none regular


BOWL = """
component BowlBead
  parameter a::Real = 0.5
  parameter g::Real = 9.81
  variable x::Real
  variable y::Real
  variable z::Real
  variable u::Real
  variable v::Real
  variable w::Real
  variable lambda::Real(guess = 1)
relations
  initial x = 0.8
  initial y = 0.1
  initial u = 0
  initial v = 1
  der(x) = u
  der(y) = v
  der(z) = w
  der(u) = -2 * lambda * x
  der(v) = -2 * lambda * y
  der(w) = -lambda * a - g
  x ^ 2 + y ^ 2 + a * z = 1.0
end
"""


def test_an_entry_that_is_one_parameter_counts_as_a_constant(tmp_path):
    """d(a * z)/dz is the parameter a alone; at its default it is a plain number, which the
    list of state sets takes as a constant entry (issue 25: compiling stopped with an
    AttributeError where the value was a Python float)."""
    path = tmp_path / "BowlBead.dyad"
    path.write_text(BOWL)
    compilation = api.compile(str(path))
    sets = set(compilation.model.variants) | {frozenset(compilation.model.metadata[DUMMIES])}
    common = {"der(der(x))", "der(der(y))", "der(der(z))"}
    assert sets == {frozenset(common | {"der(x)", "der(u)"}), frozenset(common | {"der(y)", "der(v)"}),
                    frozenset(common | {"der(z)", "der(w)"})}
