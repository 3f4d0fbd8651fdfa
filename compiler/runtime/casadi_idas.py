"""IDAS through CasADi (its VM or a compiled C library): one run from a consistent point over
given output times (`run`), or one short run to a single time (`run_to`, for a root search).
CasADi 3.8's own event support was measured and not used: it missed crossings (0.5 - x with x
rising), failed with IDA_ILL_INPUT ("tout too far back") on a pendulum and hung on a DAE whose
zero function depends on an algebraic unknown.
"""
from __future__ import annotations

import math
import threading
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import casadi as ca
import numpy as np

from .errors import SimulationFailed, SimulationInterrupted
from . import interrupts
from .idas import CapturedStderr, failure_time, idas_reason
from .integrator import COUNTERS
from .model import CompiledModel


@dataclass
class Segment:
    xs: np.ndarray                     # states at the output times reached
    zs: np.ndarray
    counters: dict = field(default_factory=dict)


SOLVERS_KEPT = 32        # IDAS objects kept per model: a few runs' segments (a sweep repeats one grid)


class _Solvers:
    """IDAS objects of one model by (time scaling, t0, output times, options), least recently
    used dropped first. Building one costs more than a short segment's integration (excavator,
    CPU: 4-6 ms on the VM, where CasADi derives the DAE's Jacobian again for every integrator; 1 ms
    in C), and a repeated run (a sweep, a benchmark) asks for the same segments again; the
    parameters and the initial point are inputs of the call, not part of the object."""

    def __init__(self):
        self._lock = threading.Lock()
        self._solvers: OrderedDict = OrderedDict()

    def get(self, key, build):
        with self._lock:
            solver = self._solvers.get(key)
            if solver is not None:
                self._solvers.move_to_end(key)
                return solver
        solver = build()
        with self._lock:
            self._solvers[key] = solver
            while len(self._solvers) > SOLVERS_KEPT:
                self._solvers.popitem(last=False)
        return solver


class IdasIntegrator:
    """IDAS on the model's DAE (its C library when it has one), one CasADi integrator call per run."""

    def __init__(self, model: CompiledModel, options: Mapping):
        self.model = model
        self.options = dict(options)
        self.dae = model.derived("idas_dae", lambda: _dae_function(model, scaled_time=False))
        self._solvers = model.derived("idas_solvers", _Solvers)

    def derivative(self, x: np.ndarray, z: np.ndarray, p: np.ndarray, t: float) -> np.ndarray:
        """der(x) at a point that solves the algebraic equations (the DAE's ode part there)."""
        return np.asarray(self.model.dae(x, z, p, t)[0], dtype=float).reshape(-1)

    def run(self, t0: float, times: Sequence[float], x0: np.ndarray, z0: np.ndarray,
            p: np.ndarray, consistent: bool = False, step0: float | None = None,
            xdot: np.ndarray | None = None) -> Segment:
        """`consistent`: (x0, z0) solve the algebraic equations already, so IDAS starts from
        der(x) = ode(x0, z0) instead of its own initial-condition search. `step0`: IDAS's first
        step (its own choice depends on the first output time, so on the output grid)."""
        options = self.options if step0 is None else dict(self.options, step0=float(step0))
        if consistent:
            xdot = self.derivative(x0, z0, p, t0) if xdot is None else xdot
            options = dict(options, calc_ic=False, init_xdot=list(xdot))
        times = [float(v) for v in times]
        solver = self._solvers.get((False, float(t0), tuple(times), _options_key(options)),
                                   lambda: _make(self.model, self.dae, t0, times, options))
        return self._call(solver, x0, z0, p, len(times), lambda tau: tau)

    def run_to(self, t0: float, t1: float, x0: np.ndarray, z0: np.ndarray, p: np.ndarray) -> Segment:
        """One short run from t0 to t1 only (a root search calls this often): the integrator is
        built once, in scaled time t = t0 + (t1 - t0) tau over tau in [0, 1]."""
        unit_step = self._solvers.get(
            (True, 0.0, (1.0,), _options_key(self.options)),
            lambda: _make(self.model, _dae_function(self.model, scaled_time=True), 0.0, [1.0], self.options))
        pp = np.concatenate([p, [t0, t1 - t0]])
        return self._call(unit_step, x0, z0, pp, 1, lambda tau: t0 + (t1 - t0) * tau)

    def _call(self, solver, x0, z0, p, n: int, model_time) -> Segment:
        model = self.model
        nx, nz, _ = model.sizes
        try:
            with CapturedStderr() as messages:
                sol = solver(x0=x0, z0=z0, p=p)
        except KeyboardInterrupt:
            reached = model_time(float(solver.stats().get("tcur", math.nan)))
            raise SimulationInterrupted(f"interrupted at t = {reached:.10g}", reached,
                                        "interrupted") from None
        except RuntimeError as err:
            reached = model_time(float(solver.stats().get("tcur", math.nan)))
            if interrupts.pending:
                # CasADi polls for Ctrl-C inside its callbacks and turns it into a failed residual
                raise SimulationInterrupted(f"interrupted at t = {reached:.10g}", reached,
                                            "interrupted") from None
            reason = idas_reason(str(err), messages.text)
            said = failure_time(messages.text)
            if said is not None and math.isfinite(said):
                reached = model_time(said)
            raise SimulationFailed(f"simulation of {model.name} failed at t = {reached:.10g}: "
                                   f"{reason}", reached, reason) from None
        return Segment(np.asarray(sol["xf"], dtype=float).reshape(nx, n),
                       np.asarray(sol["zf"], dtype=float).reshape(nz, n), _counters(solver.stats()))


def _dae_function(model: CompiledModel, scaled_time: bool) -> ca.Function:
    """The DAE as CasADi's integrator wants it: (t, x, z, p, u) -> (ode, alg, quad, zero); with
    `scaled_time`, t = t_a + t_b * tau with t_a, t_b appended to p."""
    native = model.native_dae()
    if native is not None and not scaled_time:
        return native
    sym = ca.SX.sym if native is None else ca.MX.sym
    nx, nz, npar = model.sizes
    x, z, p, t, u = sym("x", nx), sym("z", nz), sym("p", npar), sym("t"), sym("u", 0)
    if scaled_time:
        shift, span = sym("t_a"), sym("t_b")
        p_in, t_model = ca.vertcat(p, shift, span), shift + span * t
    else:
        span, p_in, t_model = 1.0, p, t
    if native is None:
        ode, alg = model.dae(x, z, p, t_model)
    else:
        ode, alg = native(t_model, x, z, p, u)[:2]
    empty = ca.SX(0, 1) if native is None else ca.MX(0, 1)
    return ca.Function("dyad_dae", [t, x, z, p_in, u], [span * ode, alg, empty, empty],
                       ca.dyn_in(), ca.dyn_out())


def _options_key(options: Mapping) -> str:
    return repr(sorted(options.items()))


def _make(model: CompiledModel, dae: ca.Function, t0: float, times: list[float], opts: dict):
    try:
        return ca.integrator("dyad_idas", "idas", dae, t0, times, opts)
    except RuntimeError as err:
        reason = str(err).strip().splitlines()[-1]
        raise SimulationFailed(f"cannot set up IDAS for {model.name}: {reason}", t0, reason) from None


def _counters(stats: Mapping) -> dict:
    out = {}
    for key, name in COUNTERS.items():
        value = stats.get(key)
        if isinstance(value, (int, float)) and math.isfinite(value):
            out[name] = int(value)
    return out
