"""The Integrator interface and its IDAS implementation (CasADi's VM or a compiled C library).

An integrator runs one segment: from (t0, x0, z0) over the output times of the segment, while
watching zero-crossing functions ("watches"). A watch of kind "record" is a state event of the
model: IDAS locates it, restarts there, and the time is logged. A watch of kind "stop" (a bound,
a degrading state set) ends the segment at the crossing; the driver decides what follows.
Another integrator is added by implementing `Integrator.run` with the same `Segment` result.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Mapping, Protocol, Sequence

import casadi as ca
import numpy as np

from .errors import SimulationFailed, SimulationInterrupted
from .idas import CapturedStderr, idas_reason
from .model import CompiledModel

COUNTERS = {"nsteps": "steps", "nfevals": "residual_evaluations", "n_call_jacF": "jacobian_evaluations",
            "nlinsetups": "linear_solver_setups", "netfails": "error_test_failures",
            "nniters": "newton_iterations", "nncfails": "newton_convergence_failures"}
MAX_EVENTS = 1_000_000


@dataclass(frozen=True)
class Watch:
    """Zero-crossing functions of (x, z, p, t), one IDAS root each, with what a crossing means."""
    function: ca.Function              # (x, z, p, t) -> column; IDAS reports crossings from + to -
    kinds: tuple[str, ...]             # "record" or "stop", per row
    labels: tuple[object, ...]         # what each row is, for the driver


@dataclass
class Segment:
    xs: np.ndarray                     # states at the output times reached
    zs: np.ndarray
    events: list[tuple[float, int]] = field(default_factory=list)   # (time, watch row), in order
    stop: tuple[float, int] | None = None                            # the crossing that ended it
    counters: dict = field(default_factory=dict)


class Integrator(Protocol):
    def run(self, t0: float, times: Sequence[float], x0: np.ndarray, z0: np.ndarray,
            p: np.ndarray, stopping: bool = True) -> Segment: ...


class _Stopped(Exception):
    pass


class _Transition(ca.Callback):
    """Called by CasADi at every located crossing: logs it, keeps the state (no jump), and ends
    the IDAS call at a "stop" crossing when stopping is on."""

    def __init__(self, nx: int, nz: int, kinds: Sequence[str]):
        ca.Callback.__init__(self)
        self.nx, self.nz, self.kinds = nx, nz, list(kinds)
        self.log: list[tuple[float, int]] = []
        self.stop: tuple[float, int] | None = None
        self.stopping = True
        self.construct("dyad_transition", {})

    def get_n_in(self): return 4
    def get_n_out(self): return 1
    def get_name_in(self, i): return ("index", "t", "x", "z")[i]
    def get_name_out(self, i): return "post_x"
    def get_sparsity_in(self, i): return ca.Sparsity.dense((1, 1, self.nx, self.nz)[i], 1)
    def get_sparsity_out(self, i): return ca.Sparsity.dense(self.nx, 1)

    def eval(self, arg):
        index, t = int(arg[0]), float(arg[1])
        self.log.append((t, index))
        if self.stopping and self.kinds[index] == "stop":
            self.stop = (t, index)
            raise _Stopped()
        return [arg[2]]


class IdasIntegrator:
    """IDAS on the model's DAE (its C library when it has one), with `watch` as root functions."""

    def __init__(self, model: CompiledModel, options: Mapping, watch: Watch | None = None):
        self.model = model
        self.options = dict(options)
        self.watch = watch if watch is not None and watch.kinds else None
        nx, nz, _ = model.sizes
        self.transition = _Transition(nx, nz, self.watch.kinds) if self.watch else None
        self.dae = self._dae_function()

    def _dae_function(self) -> ca.Function:
        model = self.model
        native = model.native_dae()
        if native is not None and self.watch is None:
            return native
        x, z, p, t = model.symbols()
        u = ca.SX.sym("u", 0)
        zero = ca.SX(0, 1) if self.watch is None else self.watch.function(x, z, p, t)
        if native is None:
            ode, alg = model.dae(x, z, p, t)
            return ca.Function("dyad_dae", [t, x, z, p, u], [ode, alg, ca.SX(0, 1), zero],
                               ca.dyn_in(), ca.dyn_out())
        mx = [ca.MX.sym(n, s.shape[0]) for n, s in (("t", t), ("x", x), ("z", z), ("p", p))]
        ode, alg = native(mx[0], mx[1], mx[2], mx[3], ca.MX(0, 1))[:2]
        zero_mx = self.watch.function(mx[1], mx[2], mx[3], mx[0])
        return ca.Function("dyad_dae", mx + [ca.MX.sym("u", 0)], [ode, alg, ca.MX(0, 1), zero_mx],
                           ca.dyn_in(), ca.dyn_out())

    def run(self, t0: float, times: Sequence[float], x0: np.ndarray, z0: np.ndarray,
            p: np.ndarray, stopping: bool = True) -> Segment:
        model = self.model
        nx, nz, _ = model.sizes
        times = [float(v) for v in times]
        opts = dict(self.options)
        if self.transition is not None:
            opts.update(transition=self.transition, max_events=MAX_EVENTS)
            self.transition.log, self.transition.stop = [], None
            self.transition.stopping = stopping
        solver = _make(model, self.dae, t0, times, opts)
        try:
            with CapturedStderr() as messages:
                sol = solver(x0=x0, z0=z0, p=p)
        except KeyboardInterrupt:
            reached = solver.stats().get("tcur", math.nan)
            raise SimulationInterrupted(f"interrupted at t = {reached:.10g}", float(reached),
                                        "interrupted") from None
        except RuntimeError as err:
            if self.transition is not None and self.transition.stop is not None:
                return Segment(np.zeros((nx, 0)), np.zeros((nz, 0)), list(self.transition.log),
                               self.transition.stop, _counters(solver.stats()))
            reached = float(solver.stats().get("tcur", math.nan))
            reason = idas_reason(str(err), messages.text)
            raise SimulationFailed(f"simulation of {model.name} failed at t = {reached:.10g}: "
                                   f"{reason}", reached, reason) from None
        log = list(self.transition.log) if self.transition is not None else []
        return Segment(np.asarray(sol["xf"], dtype=float).reshape(nx, len(times)),
                       np.asarray(sol["zf"], dtype=float).reshape(nz, len(times)),
                       log, None, _counters(solver.stats()))


def _make(model: CompiledModel, dae: ca.Function, t0: float, times: list[float], opts: dict):
    try:
        with CapturedStderr():                 # CasADi warns that its event support is new
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
