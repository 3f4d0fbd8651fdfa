"""Operating points of a compiled model: the consistent initial point, the state of a run at a
time T, or a steady state by Newton's method on [der(x); alg] = 0 with the exact Jacobian.

A model whose state set may switch is linearized in the state set active at the point: the
switcher the run uses (variants carried by the model, or the compiler's) is asked at the point.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import casadi as ca
import numpy as np

from compiler import runtime
from compiler.runtime import CompiledModel


class SteadyStateFailed(ValueError):
    """No steady state was found near the start (the residual stayed large)."""


@dataclass(frozen=True)
class OperatingPoint:
    model: CompiledModel          # the model (state set) valid at the point
    time: float
    x: np.ndarray
    z: np.ndarray
    p: np.ndarray
    steady_residual: float | None = None     # max |[der(x); alg]| for a steady state


def initial_point(model: CompiledModel, p: np.ndarray, t0: float = 0.0) -> OperatingPoint:
    start = runtime.consistent_initialization(model, p, t0)
    return OperatingPoint(model, t0, start.x, start.z, p)


def point_of_run(model: CompiledModel, p: np.ndarray, result: runtime.Result, switcher=None
                 ) -> OperatingPoint:
    """The last point of `result` (a run of `model` with parameters p), in the state set active
    there: the model of that set, its states and its algebraic unknowns solved at the point."""
    values = {name: float(result[name][-1]) for name in result.names}
    t = float(result.time[-1])
    active = _active_model(model, values, p, t, switcher)
    x = np.array([values[name] for name in active.state_names])
    z_guess = np.array([values.get(name, guess) for name, guess in zip(active.algebraic_names, active.z_guess)])
    from compiler.linear.elimination import EliminatedSystem
    z = EliminatedSystem(active, [], []).solve_algebraic(x, p, t, z_guess)
    return OperatingPoint(active, t, x, z, p)


def _active_model(model: CompiledModel, values: Mapping[str, float], p: np.ndarray, t: float,
                  switcher) -> CompiledModel:
    if switcher is None:
        switcher = runtime.default_switcher(model)
    if switcher is None:
        return model
    # the selection outputs of the model the run started in, evaluated at the point
    x = np.array([values[name] for name in model.state_names])
    z = np.array([values.get(name, guess) for name, guess in zip(model.algebraic_names, model.z_guess)])
    outputs = np.asarray(model.outputs(x, z, p, t), dtype=float).reshape(-1)
    return switcher.switch(model, {**values, **dict(zip(model.output_names, outputs))}, t)


def steady_point(start: OperatingPoint, tol: float = 1e-10, max_iterations: int = 100) -> OperatingPoint:
    """Newton (least squares where the Jacobian is singular, e.g. a free integrator) on
    der(x) = 0, alg = 0 in (x, z) from `start`, with the exact Jacobian."""
    model = start.model
    nx = len(model.state_names)
    x, z, p, t = model.symbols()
    ode, alg = model.dae(x, z, p, t)
    residual = ca.vertcat(ode, alg)
    unknowns = ca.vertcat(x, z)
    function = ca.Function("steady", [unknowns, p, t], [residual, ca.jacobian(residual, unknowns)])
    w = np.concatenate([start.x, start.z])
    r = np.asarray(function(w, start.p, start.time)[0], dtype=float).reshape(-1)
    for _ in range(max_iterations):
        r_, jac_ = function(w, start.p, start.time)
        r = np.asarray(r_, dtype=float).reshape(-1)
        if np.max(np.abs(r), initial=0.0) <= tol * (1.0 + np.max(np.abs(w), initial=0.0)):
            break
        step = np.linalg.lstsq(np.asarray(ca.densify(jac_), dtype=float), r, rcond=None)[0]
        w = w - step
        if np.max(np.abs(step), initial=0.0) <= 1e-15 * (1.0 + np.max(np.abs(w), initial=0.0)):
            r = np.asarray(function(w, start.p, start.time)[0], dtype=float).reshape(-1)
            break
    largest = float(np.max(np.abs(r), initial=0.0))
    if not np.isfinite(largest) or largest > 1e-6 * (1.0 + np.max(np.abs(w), initial=0.0)):
        raise SteadyStateFailed(f"no steady state found: the largest residual of der(x) = 0, "
                                f"alg = 0 is {largest:.3g} after Newton from the initial point")
    return OperatingPoint(model, start.time, w[:nx].copy(), w[nx:].copy(), start.p, largest)
