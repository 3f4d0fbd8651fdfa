"""Where the equations IDAS solves together stop determining their unknowns (run_failures.py): the
smallest singular value of the Jacobian of the algebraic equations with respect to the algebraic
unknowns, along a run towards a failure. This is what the solve divides by: a mass matrix or a
constraint Jacobian losing rank makes the pivots of its factorization vanish, whichever of its
entries pass through 0 on the way (Andrews' squeezer's off-diagonal entries do, harmlessly).

The run towards the failure records the states and the named signals; derivative unknowns (der(u)
solved in a block) are not among them, so the algebraic unknowns are solved again at each point,
by Newton's method from the recorded values (0 where none is recorded).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import casadi as ca
import numpy as np

from compiler.errors import Span
from compiler.model.domain_edges import domain_edge

NEWTON_STEPS = 8
# an algebraic unknown is in the vanishing direction where its share of the null vector is above this
INVOLVED = 1e-6


def singular_block(compilation, parameter_values: Mapping[str, float], env: dict[str, np.ndarray],
                    times: np.ndarray) -> tuple[str, str, Span | None] | None:
    """(words, hint, equation) where the equations IDAS solves together lose rank towards the
    failure: the smallest singular value of their Jacobian reaching 0 as a divisor does; None
    where it does not."""
    trend = smallest_pivots(compilation.model, parameter_values, env, times)
    if trend is None:
        return None
    solved = np.isfinite(trend.smallest)
    if solved.sum() < 3:
        return None
    series, at = trend.smallest[solved], times[solved]
    score, k = domain_edge("divisor", at, series)
    if score is None:
        return None
    origins = compilation.reduced.alg_origins
    origin = origins[trend.rows[0]] if trend.rows[0] < len(origins) else None
    names = _listed(block_unknowns(compilation.reduced, trend.unknowns, trend.rows))
    words = (f"the equations solved together for {names} become singular: the smallest singular value "
             f"of their Jacobian reaches 0 ({series[k]:.4g} at t = {at[k]:.6g}, "
             f"{series[k] / np.max(series):.3g} of its largest along the run)")
    hint = ("equations solved together (a mass matrix, the constraints of a mechanism) stop "
            "determining their unknowns where their Jacobian loses rank: a mass matrix that "
            "degenerates, a mechanism at a dead centre; check the parameters and the geometry there")
    return words, hint, getattr(origin, "span", None)


def block_unknowns(reduced, involved: list[str], rows: list[int]) -> list[str]:
    """The unknowns solved together with the algebraic unknowns `involved` in the algebraic
    equations `rows`: those and every assignment on a cycle through them (a mass matrix torn down to der(v) also solves der(u),
    assigned from der(v) inside the block), in the order the reduced system computes them."""
    reads = {a.target: {s.name for s in a.expr.free_symbols} for a in reduced.assignments}
    reaches_residual = {s.name for e in rows for s in reduced.alg[e].free_symbols}   # read by the rows, transitively
    frontier = list(reaches_residual)
    while frontier:
        for name in reads.get(frontier.pop(), ()):
            if name not in reaches_residual:
                reaches_residual.add(name)
                frontier.append(name)
    from_unknowns = set(involved)                              # assignments that read the unknowns, transitively
    for a in reduced.assignments:                              # in computation order: one pass suffices
        if reads[a.target] & from_unknowns:
            from_unknowns.add(a.target)
    cycle = {a.target for a in reduced.assignments} & reaches_residual & from_unknowns
    return list(involved) + [a.target for a in reduced.assignments if a.target in cycle]


def _listed(names: list[str]) -> str:
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


@dataclass(frozen=True)
class BlockTrend:
    smallest: np.ndarray        # the smallest singular value at each time (nan where unsolved)
    rows: list[int]             # algebraic equations in the vanishing pivot, most involved first
    unknowns: list[str]         # algebraic unknowns in the vanishing direction, most involved first


def smallest_pivots(model, parameter_values: Mapping[str, float], env: Mapping[str, np.ndarray],
                    times: np.ndarray) -> BlockTrend | None:
    """The trend of the algebraic Jacobian's smallest singular value over `times`, for a model
    with states and algebraic unknowns; None where the points cannot be rebuilt. (With one
    unknown it is that equation's derivative with respect to it, the assignments it reads
    included: the Schur complement of a mass matrix torn down to one unknown.)"""
    nz = len(model.algebraic_names)
    if nz < 1 or not model.state_names or any(n not in env for n in model.state_names):
        return None
    tunable = {n for n, free in zip(model.parameter_names, model.parameter_tunable) if free}
    try:
        p = model.parameter_vector({n: v for n, v in parameter_values.items() if n in tunable})
    except Exception:           # noqa: BLE001 - no parameter vector: nothing to evaluate
        return None
    newton = model.algebraic_newton()
    smallest = np.full(len(times), np.nan)
    vectors = None
    z = np.array([float(env[n][0]) if n in env else 0.0 for n in model.algebraic_names])
    for k, t in enumerate(times):
        x = np.array([float(env[n][k]) for n in model.state_names])
        recorded = np.array([float(env[n][k]) if n in env else z[i]
                             for i, n in enumerate(model.algebraic_names)])
        solved = _solve(newton, x, recorded, p, float(t))
        if solved is None:
            continue
        z, jacobian = solved
        u, sigma, vt = np.linalg.svd(jacobian)
        smallest[k] = sigma[-1]
        vectors = (u[:, -1], vt[-1])
    if vectors is None:
        return None
    shares = np.abs(vectors[0])
    rows = [int(i) for i in np.argsort(-shares, kind="stable") if shares[i] > INVOLVED * shares.max()]
    weights = np.abs(vectors[1])
    unknowns = [model.algebraic_names[int(i)] for i in np.argsort(-weights, kind="stable")
                if weights[i] > INVOLVED * weights.max()]
    return BlockTrend(smallest, rows, unknowns)


def _solve(newton, x, z, p, t):
    """(z, d alg / d z) with alg(x, z) = 0 from z, or None when Newton does not get there."""
    for _ in range(NEWTON_STEPS):
        residual, jacobian = newton(x, z, p, t)
        residual = np.asarray(residual, dtype=float).ravel()
        jacobian = np.asarray(ca.densify(jacobian), dtype=float)
        if not (np.all(np.isfinite(residual)) and np.all(np.isfinite(jacobian))):
            return None
        scale = 1.0 + np.max(np.abs(z), initial=0.0)
        step = np.linalg.lstsq(jacobian, -residual, rcond=None)[0]
        z = z + step
        if np.max(np.abs(step), initial=0.0) <= 1e-12 * scale:
            return z, jacobian
    residual = np.asarray(newton(x, z, p, t)[0], dtype=float).ravel()
    return None if np.max(np.abs(residual), initial=0.0) > 1e-8 * (1.0 + np.max(np.abs(z))) else (z, jacobian)
