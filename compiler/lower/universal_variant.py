"""Every state set of a model from one compiled system: the index-1 system before any state choice.

A model can have more state sets than are worth compiling one by one (a chain of N bodies written
in Cartesian coordinates has (3^N + 1) / 2 of them; state_set_variants.py compiles at most 64). All of
them are the same equations: the index reduction's system (compiler/structure/indexed.py) with
every variable and every derivative variable an unknown. A choice of dummy derivatives only says
which variables are states, der(v) = (the unknown der(v)), and which are algebraic. So the model
carries that system once, lowered with no states (`universal_model`), and the runtime makes the
model of any choice from it by permuting its unknowns, without the compiler
(compiler/runtime/universal.py). The system is not torn: each such variant integrates every
unknown, where a variant compiled by itself solves some of them explicitly.
"""
from __future__ import annotations

import dataclasses

import sympy

from compiler import runtime
from compiler.runtime.universal import UNIVERSAL
from compiler.lower.to_casadi import lower
from compiler.structure.state_selection.monitored import stand_in_pairs
from compiler.structure.reduce import Analysis
from compiler.structure.reduced import InitialProblem, ReducedSystem



def universal_model(analysis: Analysis, reduced: ReducedSystem) -> runtime.CompiledModel:
    """The model of the index-1 system with every unknown algebraic. `reduced` is a state set's
    reduced system with the selection outputs (state_set_variants.build_variant): its parameters,
    its outputs and the observables that compute outputs that are no unknown here are kept.

    Its metadata[UNIVERSAL] holds {"equations": how many of its algebraic residuals are equations,
    "derivative": {v: der(v)} for every variable whose derivative is an unknown, "stand_ins": [[kept, stand_in], ...]} (see `stand_in_pairs`)."""
    system = analysis.system
    unknowns = list(system.names)
    known = set(unknowns)
    observables = [a for a in reduced.observables
                   if a.target not in known and not a.target.startswith("__pivot")]
    outputs = [n for n in reduced.output_names if not n.startswith("__pivot")]
    # as many residuals as unknowns for the lowering: the rows past the equations are 0 and unused
    padding = [sympy.S.Zero] * (len(unknowns) - system.n_eqs)
    universal = dataclasses.replace(
        reduced, states=[], ode=[], algebraics=unknowns, alg=list(system.equations) + padding,
        alg_origins=list(system.origins), assignments=[], observables=observables,
        output_names=outputs, initial=InitialProblem([], [], dict(reduced.initial.guesses)))
    model = lower(universal)
    derivative = {system.names[v]: system.names[d] for v, d in enumerate(system.var_to_diff) if d >= 0}
    return model.replace(metadata={**model.metadata, UNIVERSAL: {
        "equations": system.n_eqs, "derivative": derivative,
        # ddphi only stands in for dw where dw is kept as a state (w = der(phi) holds)
        "stand_ins": [[system.names[a], system.names[b]] for a, b in sorted(set(stand_in_pairs(system)))
                      if a >= 0]}})


def with_universal(analysis: Analysis, variant):
    """`variant` (state_set_variants.Variant) whose model carries the universal system too."""
    return dataclasses.replace(variant, model=variant.model.replace(
        universal=universal_model(analysis, variant.reduced)))
