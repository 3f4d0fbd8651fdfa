"""A switch of the state set during a run: the variant the switcher picks at the crossing, the
consistent point it continues from, the switch log entry; and how an IDAS failure of a model
with state sets is explained."""
from __future__ import annotations

from itertools import combinations
from typing import Mapping

import numpy as np

from .errors import SimulationFailed
from .initialization import restart_point
from .model import CompiledModel
from .model_code import code_stats
from .outputs import evaluate_outputs, polish_algebraics
from .state_sets import level_matrix, state_selection_quality


def explained(model: CompiledModel, failure: SimulationFailed) -> SimulationFailed:
    """An IDAS failure of a model whose state set is monitored: name the constraints whose dummy
    derivatives may have gone singular before the check could see it."""
    if not model.state_sets:
        return failure
    sets = "; ".join(", ".join(level["candidates"]) for level in model.state_sets)
    hint = (f"; the state set ({', '.join(model.state_names)}) of this model is chosen among the "
            f"derivatives of its constraints ({sets}) and may have become singular here")
    return SimulationFailed(str(failure) + hint, failure.time_reached, (failure.reason or "") + hint,
                            failure.variable)


def switch_state_set(run, model: CompiledModel, values: Mapping[str, float], t: float, p, x, z, level: int):
    """Continue in the state set that the switcher chooses at this point."""
    current = model.state_sets[level]
    dummies = ", ".join(current["candidates"][j] for j in current["chosen"])
    if run.switcher is None:
        reason = (f"its state set ({', '.join(model.state_names)}) degrades here (the pivot block of "
                  f"the dummy derivatives {dummies} is close to singular); this model carries one "
                  f"state set: simulate it with dyadc, which switches state sets")
        raise SimulationFailed(f"simulation of {model.name} stopped at t = {t:.10g}: {reason}", t, reason)
    new = run.switcher.switch(model, values, t)
    column = np.array([values.get(n, np.nan) for n in model.output_names], dtype=float)
    if new.state_names == model.state_names:
        reason = singular_everywhere(current, column)
        raise SimulationFailed(f"simulation of {model.name} failed at t = {t:.10g}: {reason}", t, reason)
    quality, _ = state_selection_quality(model.state_sets, column)
    run.switches.append({"time": float(t), "from": list(model.state_names), "to": list(new.state_names),
                         "degraded": dummies, "quality": float(quality), **code_stats(new)})
    p_new = run.parameter_vectors.get(id(new))        # the same for every visit of a state set
    if p_new is None:
        p_new = run.parameter_vectors[id(new)] = new.parameter_vector(run.options.params)
    x_target = np.array([values[n] for n in new.state_names])
    z_guess = np.array([values.get(n, 0.0) for n in new.algebraic_names])
    # an integrator that solves the algebraic equations itself to round-off (the native driver:
    # Newton steps in C, 15 us against the least-squares search's 160) saves the search
    solve = getattr(run.integrator(new), "algebraic_solution", None)
    solved = solve(t, x_target, z_guess, p_new) if solve is not None else None
    if solved is not None:
        return new, x_target, solved, p_new
    point = restart_point(new, p_new, t, x_target, z_guess)
    return new, point.x, point.z, p_new


SETS_LISTED = 6


def singular_everywhere(level: Mapping, column: np.ndarray) -> str:
    """Why no state set serves at this point: every choice of dummy derivatives for the level's
    constraints, with the smallest singular value of its pivot block (best first), and the largest
    entry of the constraints' Jacobian for scale."""
    matrix = level_matrix(level, column)
    rows, names = int(level["rows"]), list(level["candidates"])
    sets = []
    for choice in combinations(range(len(names)), rows):
        block = matrix[:, list(choice)]
        sigma = float(np.linalg.svd(block, compute_uv=False)[-1]) if np.all(np.isfinite(block)) else np.nan
        sets.append((sigma, [names[j] for j in choice]))
    sets.sort(key=lambda item: -item[0] if np.isfinite(item[0]) else np.inf)
    listed = "; ".join(f"{{{', '.join(choice)}}}: {sigma:.3g}" for sigma, choice in sets[:SETS_LISTED])
    more = f"; and {len(sets) - SETS_LISTED} more" if len(sets) > SETS_LISTED else ""
    largest = float(np.nanmax(np.abs(matrix))) if matrix.size else 0.0
    return (f"the state selection is singular here: no choice of dummy derivatives among "
            f"{', '.join(names)} for the {rows} constraint(s) relating them has a regular pivot "
            f"(smallest singular value of each choice's pivot block: {listed}{more}; largest entry "
            f"of the constraints' Jacobian: {largest:.3g})")


def all_outputs(model: CompiledModel, x, z, p, t: float, settled: bool = False) -> np.ndarray:
    """Every output at one point; z polished by Newton steps first unless `settled` (it solves
    the algebraic equations to round-off already: Stop.settled)."""
    xs, zs = np.asarray(x).reshape(-1, 1), np.asarray(z).reshape(-1, 1)
    # every Newton step: the next state set starts from these values (SETTLED's second-step test
    # lost the A01 pendulum 0.13 digits over 100 s at rtol 1e-10)
    if not settled:
        zs = polish_algebraics(model, xs, zs, p, np.array([t]), settled=0.0)
    return evaluate_outputs(model, xs, zs, p, np.array([t]))[:, 0]
