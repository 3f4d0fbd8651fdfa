"""Why a run failed, in words and at an equation (issue 19, item 10): IDAS reports only a flag
(IDA_FIRST_RES_FAIL, IDA_TOO_MUCH_WORK, ...) and a time. Most such failures of a model that
compiled come from an operation leaving its domain: a divisor, or the argument of a square root
or logarithm, reaching or crossing zero; asin/acos beyond +-1; the factor of a derivative (a
mass) or the derivative of an algebraic equation with respect to its unknown (z^2 = 1 - time)
reaching zero, where the solve divides by it (the unknown the equation is solved for alone: an
off-diagonal mass-matrix entry through 0 is no culprit); the equations IDAS solves together losing
rank (singular_blocks.py: a mass matrix that degenerates); else a variable blowing up in finite
time (der(x) = x^2). This module looks for one.

Where the run was: the model is run again from the start to just before the failure time, with
output times crowding towards it (at most two such runs; IDAS fills the failure's partial result
only at the end of a segment, so that may hold nothing near the failure); a run that failed at
its start is looked at in its consistent initial point. Each candidate subexpression of the flat
equations (outside `ifelse` branches, which guard theirs) is evaluated there; the one out of its
domain first, else the one whose trend reaches the edge soonest, names the equation. When none
is near its edge, the solver's words stand.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np
import sympy

from compiler.errors import Note, SimulationError, Span
from compiler.model.domain_edges import domain_edge
from compiler.model.flat import TIME
from compiler.model.singular_blocks import singular_block

# A variable this many times its median size along the run, still growing, is blowing up.
BLOW_UP = 1e3
# Candidates evaluated per failure at most (the largest models have thousands of equations).
MAX_CANDIDATES = 5000


@dataclass(frozen=True)
class _Candidate:
    kind: str                   # "divisor" | "sqrt" | "log" | "asin" | "coefficient" | "jacobian"
    operand: sympy.Expr         # the value that must stay in the domain
    shown: sympy.Expr           # the subexpression, for the message
    span: Span | None
    path: str


def diagnose(error: SimulationError, compilation, parameter_values: Mapping[str, float],
             start: float, run=None) -> SimulationError:
    """`error` with its cause in words and its location, when a domain edge or a blow-up explains
    it; else `error` itself. `run`: (model, integrator maker) of the failed run, which the run
    towards the failure repeats (another integrator fails elsewhere); default the compilation's
    model on the runtime's own integrator."""
    points = _points(error, compilation, parameter_values, start, run)
    if points is None:
        return error
    times, env = points
    states = set(compilation.reduced.states)
    found = _worst(_candidates(compilation.flat, states, _solved_for(compilation.reduced)), env, times)
    if found is not None:
        candidate, value, where = found
        words, hint, span = _words(candidate, value, where), _HINTS[candidate.kind], candidate.span
    else:
        explanation = singular_block(compilation, parameter_values, env, times) or \
            _blow_up(compilation.flat, env, times)
        if explanation is None:
            return error
        words, hint, span = explanation
    t = error.time_reached if error.time_reached is not None else float(times[-1])
    explained = SimulationError(f"simulation of {compilation.model.name} failed at t = {t:.10g}: {words}",
                                error.time_reached, words, hint=hint)
    explained.span = span
    explained.partial = error.partial
    explained.notes = [Note(f"the solver reported: {error.message}")]
    return explained


_HINTS = {
    "divisor": "a division by a value that reaches 0 makes the equations infinite; guard it (e.g. "
               "max(abs(d), eps)) or stop the run before it happens",
    "sqrt": "the square root of a negative value is not real; check the signs, or the start values "
            "of the variables in it",
    "log": "the logarithm of a value at or below 0 is not real; check the signs, or the start values "
           "of the variables in it",
    "coefficient": "where the factor of a derivative vanishes (a mass, a capacitance, an inertia "
                   "of 0) the equation no longer determines it; keep that factor away from 0",
    "jacobian": "an algebraic equation whose derivative with respect to its unknown vanishes has a "
                "double root there and often no real solution beyond it (z^2 = 1 - time at t = 1)",
    "asin": "asin and acos take values in [-1, 1]; check the argument's scale",
}


def _words(candidate: _Candidate, value: float, where: str) -> str:
    shown = _text(candidate.shown)
    operand = _text(candidate.operand)
    if candidate.kind == "divisor":
        return f"the divisor `{operand}` in `{shown}` reaches 0 ({operand} = {value:.4g} {where})"
    if candidate.kind == "coefficient":
        return (f"the factor `{operand}` of `{shown}` in this equation reaches 0, so nothing determines "
                f"{shown} any more ({operand} = {value:.4g} {where})")
    if candidate.kind == "jacobian":
        return (f"this equation stops determining `{shown}`: its derivative with respect to {shown}, "
                f"`{operand}`, reaches 0 ({value:.4g} {where}); past that point it may have no solution")
    if candidate.kind == "asin":
        return f"the argument of `{shown}` leaves [-1, 1] ({operand} = {value:.4g} {where})"
    name = "square root" if candidate.kind == "sqrt" else "logarithm"
    if value < 0 or (candidate.kind == "log" and value == 0):
        return f"`{shown}` takes the {name} of a negative number ({operand} = {value:.4g} {where})"
    return f"`{shown}` takes the {name} of a value that reaches 0 ({operand} = {value:.4g} {where})"


def _text(expr: sympy.Expr) -> str:
    text = str(expr)
    return text if len(text) <= 60 else text[:57] + "..."


# ------------------------------------------------------------------------ where the run was

def _points(error: SimulationError, compilation, parameter_values: Mapping[str, float],
            start: float, run=None) -> tuple[np.ndarray, dict[str, np.ndarray]] | None:
    """Times and name -> values there: a run again from the start to just before the failure time,
    with output times crowding towards it (IDAS fills the partial result only at the end of a
    segment, so it may hold nothing near the failure), or the start point for a failure there."""
    model = compilation.model
    t_fail = error.time_reached
    if t_fail is not None and t_fail > start:
        found = _run_towards(*(run or (model, None)), parameter_values, start, t_fail)
        if found is None:
            return None
    else:
        try:
            p = np.array([parameter_values.get(n, d) for n, d in
                          zip(model.parameter_names, model.parameter_defaults)], dtype=float)
            x, z = np.asarray(model.x_guess, dtype=float), np.asarray(model.z_guess, dtype=float)
            try:                    # the consistent point IDAS started from, where there is one
                from compiler.runtime import consistent_initialization
                point = consistent_initialization(model, p, start)
                x, z = point.x, point.z
            except Exception:       # noqa: BLE001 - the start values are the next best point
                pass
            out = np.asarray(model.outputs(x, z, p, start), dtype=float).ravel()
        except Exception:           # noqa: BLE001 - no start point to look at: the solver's words stand
            return None
        found = np.array([start], dtype=float), {n: np.array([v]) for n, v in zip(model.output_names, out)}
    times, values = found
    values[TIME.name] = times
    for name, value in parameter_values.items():
        values.setdefault(name, np.full(len(times), float(value)))
    return times, values


def _run_towards(model, integrator, parameter_values: Mapping[str, float], start: float, t_fail: float):
    from compiler import runtime
    span = t_fail - start
    for closest in (1e-6, 1e-2):        # at most two more runs: a failure costs at most 3 runs
        grid = sorted({start + span * (1 - 0.5 ** k) for k in range(40) if 0.5 ** k > closest}
                      | {start + span * (1 - closest)} | {start + span * j / 20 for j in range(20)})
        try:
            result = runtime.simulate(model, options=runtime.SimulationOptions(
                stop=grid[-1], start=start, saveat=grid, params=dict(parameter_values), progress=False,
                integrator=integrator))
        except Exception:           # noqa: BLE001 - it fails before that point too: stop earlier
            continue
        return np.asarray(result.time, dtype=float), {n: np.asarray(result[n], dtype=float)
                                                      for n in result.names}
    return None


# ------------------------------------------------------------------------ what can leave its domain

def _candidates(flat, states: set[str], solved_for: dict[int, set[str]]) -> list[_Candidate]:
    found: list[_Candidate] = []
    unknowns = {v.name for v in flat.variables} - states
    for equation in flat.equations:
        span = getattr(equation.origin, "span", None)
        path = getattr(equation.origin, "path", "")
        pivots = {name for name in solved_for.get(id(equation.origin), ())
                  if name.startswith("der(") or name in unknowns}
        found.extend(_coefficients(equation.residual, pivots, span, path))
        for node in _unguarded(equation.residual):
            if len(found) >= MAX_CANDIDATES:
                return found
            candidate = _restricted(node, span, path)
            if candidate is not None:
                found.append(candidate)
    return found


def _solved_for(reduced) -> dict[int, set[str]]:
    """The unknowns each flat equation (by the identity of its origin) is solved for alone, where a
    solve divides by the equation's factor of that unknown: the target of an assignment made from it
    (target = rest / factor), or the one algebraic unknown of an algebraic residual that has no
    other (IDAS's Newton divides by its derivative). An unknown of a block of several (a mass
    matrix, an algebraic loop) is found by factorizing the block: its entries are no pivots, and an
    off-diagonal one passing through 0 makes nothing singular (Andrews' squeezer, failing at rtol
    1e-11 before 6a29c6e, was blamed on `e*lambda[3]*sin(Phi + delta) - ...`, the derivative of a
    mass-matrix row with respect to the angle delta, which the closure conditions determine)."""
    solved: dict[int, set[str]] = {}
    for assignment in reduced.assignments:
        if assignment.origin is not None:
            solved.setdefault(id(assignment.origin), set()).add(assignment.target)
    algebraics = set(reduced.algebraics)
    for residual, origin in zip(reduced.alg, reduced.alg_origins):
        alone = [s.name for s in residual.free_symbols if s.name in algebraics]
        if origin is not None and len(alone) == 1:
            solved.setdefault(id(origin), set()).add(alone[0])
    return solved


def _unguarded(expr: sympy.Expr):
    """The subexpressions of `expr` outside selections: `ifelse(x > 0, sqrt(x), 0)` guards its
    square root, which is evaluated only where the condition holds."""
    stack = [expr]
    while stack:
        node = stack.pop()
        yield node
        if not isinstance(node, sympy.Piecewise):
            stack.extend(node.args)


def _coefficients(residual: sympy.Expr, pivots: set[str], span: Span | None,
                  path: str) -> list[_Candidate]:
    """The factor of each derivative the equation is solved for (`pivots`, _solved_for), in an
    equation linear in it: where it reaches 0 the derivative is no longer determined (a mass that
    vanishes); likewise the derivative of the equation with respect to an algebraic unknown it is
    solved for (z^2 = 1 - time at t = 1)."""
    found = []
    for symbol in sorted(residual.free_symbols, key=lambda s: s.name):
        derivative = symbol.name.startswith("der(")
        if symbol.name not in pivots:
            continue
        factor = sympy.diff(residual, symbol)
        if factor.is_number or any(s.name.startswith("der(") for s in factor.free_symbols):
            continue
        found.append(_Candidate("coefficient" if derivative else "jacobian", factor, symbol, span, path))
    return found


def _blow_up(flat, env: dict[str, np.ndarray], times: np.ndarray) -> tuple[str, str, Span | None] | None:
    """(words, hint, declaration) of the variable that grows fastest towards the failure, when one
    grows by more than BLOW_UP times its typical size along the run: a finite-time blow-up."""
    best = None
    for variable in flat.variables:
        series = env.get(variable.name)
        if series is None or len(series) < 3 or not np.isfinite(series).all():
            continue
        typical = float(np.median(np.abs(series)))
        last = abs(float(series[-1]))
        if last <= BLOW_UP * max(typical, 1e-300) or not abs(series[-1]) > abs(series[-2]) > abs(series[-3]):
            continue
        ratio = last / max(typical, 1e-300)
        if best is None or ratio > best[0]:
            best = (ratio, variable, float(series[-1]), float(times[-1]))
    if best is None:
        return None
    _, variable, value, t = best
    words = (f"`{variable.name}` grows without bound ({variable.name} = {value:.4g} at t = {t:.6g}, "
             f"{best[0]:.3g} times its typical size in this run): the solution blows up in finite time")
    return words, ("a quantity that grows faster than linearly in itself (der(x) = x^2) reaches "
                   "infinity in finite time; check the signs and the powers in its equations"), \
        getattr(variable.origin, "span", None)


def _restricted(node, span: Span | None, path: str) -> _Candidate | None:
    if isinstance(node, sympy.Pow) and node.exp.is_number:
        if node.exp.is_negative and not node.base.is_number:
            return _Candidate("divisor", node.base, node, span, path)
        if node.exp.is_Rational and not node.exp.is_integer and not node.base.is_number:
            return _Candidate("sqrt", node.base, node, span, path)
    if isinstance(node, sympy.log) and not node.args[0].is_number:
        return _Candidate("log", node.args[0], node, span, path)
    if isinstance(node, (sympy.asin, sympy.acos)) and not node.args[0].is_number:
        return _Candidate("asin", node.args[0], node, span, path)
    return None


def _worst(candidates: list[_Candidate], env: dict[str, np.ndarray], times: np.ndarray):
    """(candidate, its value at the point that matters, 'at t = ...') of the operation out of its
    domain first, else the one whose trend reaches the edge soonest after the last time; None
    when none is near."""
    best = None
    for candidate in candidates:
        names = sorted(s.name for s in candidate.operand.free_symbols)
        if any(name not in env for name in names):
            continue
        try:
            function = sympy.lambdify([sympy.Symbol(n) for n in names], candidate.operand, "numpy")
            with np.errstate(all="ignore"):
                series = np.broadcast_to(np.asarray(function(*(env[n] for n in names)), dtype=float),
                                         times.shape)
        except Exception:           # noqa: BLE001 - an operand numpy cannot evaluate is no culprit
            continue
        score, k = domain_edge(candidate.kind, times, series)
        if score is not None and (best is None or score < best[0]):
            best = (score, candidate, float(series[k]), f"at t = {times[k]:.6g}")
    if best is None:
        return None
    return best[1], best[2], best[3]
