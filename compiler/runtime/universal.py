"""The model of any state set, made at run time from the one system every state set shares.

A model with more state sets than the compiler derives one by one carries its index-1 system with
every unknown algebraic (`CompiledModel.universal`, compiler/lower/universal_variant.py). For a
choice of dummy derivatives D, a variable v whose derivative der(v) is an unknown is a state when
neither v nor der(v) is in D, with der(v) = (the unknown der(v)); every other unknown is
algebraic. The variant's functions are the universal ones with their inputs permuted (CasADi
inlines them: no compiler, no sympy), and its monitored levels (`state_sets`) follow the choice by
the rules the compiled variants' do (selection_rules.may_degrade): the levels of the selection
layout whose candidates outnumber their rows and whose chosen pivot block depends on the unknowns.
So a generated module switches to every state set the in-process run reaches.
"""
from __future__ import annotations

from typing import Mapping

import casadi as ca

from .model import CompiledModel
from .model_code import made_at_run_time
from . import variants
from .selection_rules import folded_level, may_degrade, next_candidates, watched_level
from .variants import DUMMIES, SELECTION, selection_output

UNIVERSAL = "universal_system"          # metadata written by compiler/lower/universal_variant.py
ZERO = "__zero"                         # an output that is 0: a structurally zero Jacobian entry


def variant_of(universal: CompiledModel, dummies: frozenset[str], selection: Mapping) -> CompiledModel:
    """The model of the state set whose dummy derivatives are `dummies`."""
    info = universal.metadata[UNIVERSAL]
    derivative: Mapping[str, str] = info["derivative"]
    unknowns = list(universal.algebraic_names)
    states = [v for v in unknowns if v in derivative and v not in dummies and derivative[v] not in dummies]
    state_set = set(states)
    candidates = [v for v in unknowns if v not in state_set]
    x = ca.SX.sym("x", len(states))
    symbols = [ca.SX.sym(f"z{j}") for j in range(len(candidates))]
    p, t = ca.SX.sym("p", len(universal.parameter_names)), ca.SX.sym("t")
    where = {name: x[i] for i, name in enumerate(states)}
    where.update({name: symbols[j] for j, name in enumerate(candidates)})
    u = ca.vertcat(*[where[name] for name in unknowns]) if unknowns else ca.SX(0, 1)
    none = ca.SX(0, 1)
    residuals = universal.dae(none, u, p, t)[1][:int(info["equations"])]
    kept, alg, solved = explicit_unknowns(residuals, symbols)
    algebraics = [candidates[j] for j in kept]
    z = ca.vertcat(*[symbols[j] for j in kept]) if kept else ca.SX(0, 1)
    u = ca.substitute(u, ca.vertcat(*[symbols[j] for j in solved]), ca.vertcat(*solved.values())) \
        if solved else u
    where = {name: u[i] for i, name in enumerate(unknowns)}
    ode = ca.vertcat(*[where[derivative[s]] for s in states]) if states else ca.SX(0, 1)
    values = ca.vertcat(universal.outputs(none, u, p, t), ca.SX.zeros(1, 1))
    output_names = list(universal.output_names) + [ZERO]
    inputs, labels = [x, z, p, t], ["x", "z", "p", "t"]
    events = None
    if universal.events is not None:
        events = ca.Function("events", inputs, [universal.events(none, u, p, t)], labels, ["zero"])
    guesses = dict(zip(universal.algebraic_names, universal.z_guess))
    model = CompiledModel(
        name=universal.name, state_names=states, algebraic_names=algebraics,
        parameter_names=universal.parameter_names, parameter_defaults=universal.parameter_defaults,
        parameter_tunable=universal.parameter_tunable, output_names=output_names,
        x_guess=[guesses.get(s, 0.0) for s in states], z_guess=[guesses.get(s, 0.0) for s in algebraics],
        dae=ca.Function("dae", inputs, [ode, alg], labels, ["ode", "alg"]),
        init=ca.Function("init", inputs, [alg], labels, ["residuals"]),
        outputs=ca.Function("outputs", inputs, [values], labels, ["values"]),
        params=universal.params, nominals=universal.nominals,
        events=events, event_labels=universal.event_labels,
        time_events=universal.time_events, time_event_labels=universal.time_event_labels,
        metadata={**{k: v for k, v in universal.metadata.items() if k != UNIVERSAL},
                  DUMMIES: sorted(dummies), SELECTION: dict(selection)})
    levels = watched_levels(selection, dummies, info.get("stand_ins", ()), output_names, values,
                            ca.vertcat(x, z, t))
    return model.replace(state_sets=levels)


def explicit_unknowns(residuals: ca.SX, symbols: list) -> tuple[list[int], ca.SX, dict]:
    """Unknowns that an equation gives explicitly, solved for and substituted: the equation is
    linear in one of them with a constant coefficient (an alias such as der(x) = vx, mostly) and
    holds no unknown solved before (so the coefficient is the one after substitution). Returns
    the unknowns kept (positions in `symbols`), their residuals, and {position: expression in the
    kept unknowns} of the solved ones. Without this the state sets made from the universal system
    carry several times the unknowns of a compiled one (an 8-body chain: 82 against 16), and dense
    Newton steps on them cost the run most of its time."""
    position = {symbols[j].name(): j for j in range(len(symbols))}
    solved_names: set[str] = set()
    order: list[tuple[int, ca.SX]] = []
    used: set[int] = set()
    # one Jacobian of every residual (a Jacobian per entry cost 0.1 s at a 32-body chain)
    jacobian = ca.jacobian(residuals, ca.vertcat(*symbols)) if symbols else ca.SX(residuals.numel(), 0)
    colind, rows_of = jacobian.sparsity().get_ccs()
    entries = jacobian.nonzeros()
    entry_of: dict[tuple[int, int], ca.SX] = {}
    for j in range(len(symbols)):
        for k in range(colind[j], colind[j + 1]):
            entry_of[(rows_of[k], j)] = entries[k]
    for i in range(residuals.numel()):
        row = residuals[i]
        names = [symbol.name() for symbol in ca.symvar(row)]
        if any(name in solved_names for name in names):
            continue
        for name in names:
            j = position.get(name)
            coefficient = entry_of.get((i, j)) if j is not None else None
            if coefficient is None or not coefficient.is_constant() or float(ca.evalf(coefficient)) == 0.0:
                continue
            order.append((j, -ca.substitute(row, symbols[j], ca.SX(0)) / float(ca.evalf(coefficient))))
            solved_names.add(name)
            used.add(i)
            break
    remaining = [residuals[i] for i in range(residuals.numel()) if i not in used]
    if order:
        values, remaining = ca.substitute_inplace([symbols[j] for j, _ in order],
                                                  [value for _, value in order], remaining, False)
        solved = {j: value for (j, _), value in zip(order, values)}
    else:
        solved = {}
    kept = [j for j in range(len(symbols)) if j not in solved]
    return kept, (ca.vertcat(*remaining) if remaining else ca.SX(0, 1)), solved


def watched_levels(selection: Mapping, dummies: frozenset[str], stand_in_pairs, output_names: list[str],
                   values: ca.SX, varying_in: ca.SX) -> list[dict]:
    """The levels of the choice `dummies` that can degrade, in the runtime's plain form
    (CompiledModel.state_sets): each level folded (selection_rules.folded_level) and watched
    where selection_rules.may_degrade says so, an entry varying where its output depends on
    `varying_in` (the unknowns and time, as symbols of `values`)."""
    at = {name: i for i, name in enumerate(output_names)}
    levels = selection["levels"]
    candidates = set(levels[0]["order"]) if levels else set()
    out = []
    for k, level in enumerate(levels):
        order = [c for c in level["order"] if c in candidates]
        folds = variants.level_folds(level, order)
        chosen = [c for c in order if c in dummies]
        folded = folded_level(range(int(level["rows"])), order, chosen, [(int(r), u, w) for r, u, w in folds])
        priority = level["priority"]

        def entry(i: int, c: str, k=k) -> int:
            return at.get(selection_output(k, i, c), at[ZERO])

        def varies(c: str) -> bool:
            return any(ca.depends_on(values[entry(i, c)], varying_in) for i in folded.rows)

        if may_degrade(len(folded.rows), folded.candidates, folded.chosen, priority, stand_in_pairs, varies):
            out.append(watched_level(len(folded.rows), folded.candidates,
                                     [folded.candidates.index(c) for c in folded.chosen],
                                     [priority[c] for c in folded.candidates],
                                     [entry(i, c) for i in folded.rows for c in folded.candidates]))
        candidates = next_candidates(chosen, {u: w for _, u, w in folds}, level["next"])
    return out


class UniversalSwitcher:
    """The runtime's StateSetSwitcher for a model with a universal system: at a switch point, the
    model of the choice variants.dummy_choice makes there (as VariantSwitcher does among compiled
    variants), made once per model and choice and kept with the model."""

    def __init__(self, model: CompiledModel):
        self.first = model
        self.selection = model.metadata[SELECTION]
        self.public_names = list(self.selection["public"])

    def switch(self, model: CompiledModel, values: Mapping[str, float], t: float) -> CompiledModel:
        dummies = variants.dummy_choice(self.selection["levels"], values)
        if dummies is None:
            return model                      # no regular choice here: the driver reports it
        if dummies == frozenset(self.first.metadata.get(DUMMIES, ())):
            return self.first
        return self.first.derived(("universal variant", dummies), lambda: made_at_run_time(
            variant_of(self.first.universal, dummies, self.selection), self.first))
