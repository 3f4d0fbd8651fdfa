"""The Integrator of today's runs: IDAS through CasADi (casadi_idas.py), which has no root finding,
with the watched functions sampled at CHECKS_PER_SEGMENT check times per call. The check times
depend only on where a call starts and ends, never on the output grid; the first sign change
between two checks is located by a root search on short IDAS runs (crossings.py)."""
from __future__ import annotations

from dataclasses import replace
from typing import Mapping

import numpy as np

from .casadi_idas import IdasIntegrator
from .checks import check_divergence
from .crossings import before_failure, first_crossing, next_horizon, watched_values
from .errors import SimulationFailed
from .integrator import FAILED, REACHED, UNCONFIRMED, Call, Stop, Tally
from .model import CompiledModel
from .segments import first_step
from .together import earliest_crossing
from .watches import Watch

CHECKS_PER_SEGMENT = 200


class SampledIdas:
    """Integrator (integrator.py) on CasADi's IDAS: crossings are found after each call."""
    locates_crossings = False
    name = "casadi"

    def __init__(self, model: CompiledModel, options: Mapping, watch: Watch | None, tally: Tally,
                 why: str | None = None):
        self.why = why                    # why it runs where the native driver was the first choice
        self.model = model
        self.idas = IdasIntegrator(model, options)
        self.watch = watch
        self.tally = tally

    def advance(self, call: Call) -> Stop:
        """IDAS over the call's outputs and check times; the first crossing at the checks, if
        any, is where it stops."""
        # its time lists are merged and searched as Python floats
        call = replace(call, outputs=np.asarray(call.outputs, dtype=float).tolist())
        if call.checks is None:
            checks = [] if self.watch is None else \
                list(np.linspace(call.t0, call.reach, CHECKS_PER_SEGMENT + 1)[1:])
            xdot = self.idas.derivative(call.x0, call.z0, call.p, call.t0)
            step0 = first_step(self.idas, call.x0, xdot, call.t0, call.reach)
        else:
            # a call that failed, cut at its last check before the failure: the same check times
            # and first step, so that what follows does not depend on where IDAS stopped
            checks, xdot, step0 = list(call.checks), None, call.step0
        times = sorted(set(call.outputs) | {call.reach} | set(checks))
        try:
            # every call starts from a point that solves the algebraic equations already (the
            # initialization, a located crossing, the end of a call): IDAS's own initial-condition
            # search would make the run depend on the first output time
            segment = self.idas.run(call.t0, times, call.x0, call.z0, call.p, consistent=True,
                                    step0=step0, xdot=xdot)
        except SimulationFailed as failure:
            shorter = before_failure(self.watch, checks, failure, call.t0)
            retry = None if shorter is None else replace(
                call, reach=shorter, checks=tuple(c for c in checks if c <= shorter), step0=step0,
                retry=True)
            return Stop(FAILED, call.t0, call.x0, call.z0, failure=failure, retry=retry)
        self.tally(segment.counters)
        if self.watch is None:
            return self._reached(call, times, segment, None, checks)
        watched = watched_values(self.watch, call.t0, call.x0, call.z0, call.p, times, checks, segment)
        crossing = first_crossing(self.model, self.watch, call.t0, call.p, times, checks, segment,
                                  watched, call.ignored)
        if crossing is None:
            return self._reached(call, times, segment, watched, checks)
        return self._crossed(call, times, segment, crossing)

    def _reached(self, call: Call, times, segment, watched, checks) -> Stop:
        check_divergence(self.model, np.asarray(times), segment.xs, call.scale)
        at = np.searchsorted(times, call.outputs)
        horizon = None
        if self.model.state_sets:
            horizon = next_horizon(self.watch, call.t0, checks, watched, call.horizon)
        return Stop(REACHED, call.reach, segment.xs[:, -1], segment.zs[:, -1],
                    [(call.outputs, segment.xs[:, at], segment.zs[:, at])], horizon=horizon)

    def _crossed(self, call: Call, times, segment, crossing) -> Stop:
        """The crossing between two checks: a state set's at the check after it (any point past
        the crossing serves: the switch chooses the best set there, and the new set's indicator
        starts far from zero); an event's or a bound's located by a root search from the check
        before it, with the outputs past that check computed again from there."""
        t_right, t_left, row = crossing
        kind, what = self.watch.labels[row]
        reached = int(np.searchsorted(times, t_right))
        check_divergence(self.model, np.asarray(times[:reached]), segment.xs[:, :reached], call.scale)
        outputs = call.outputs
        n_out = int(np.searchsorted(outputs, t_left, side="right"))
        at = np.searchsorted(times, outputs[:n_out])
        samples = [(outputs[:n_out], segment.xs[:, at], segment.zs[:, at])]
        if kind == "state set":
            right = times.index(t_right)
            n_right = int(np.searchsorted(outputs, t_right, side="right"))
            at = np.searchsorted(times, outputs[n_out:n_right])
            samples.append((outputs[n_out:n_right], segment.xs[:, at], segment.zs[:, at]))
            return Stop(kind, t_right, segment.xs[:, right], segment.zs[:, right], samples, row, what)
        left = times.index(t_left) if t_left in times else -1
        x_left, z_left = (segment.xs[:, left], segment.zs[:, left]) if left >= 0 else (call.x0, call.z0)
        t_cross, x_cross, z_cross, crossed, row, together = earliest_crossing(
            self.tally, self.idas, self.watch, row, t_left, t_right, x_left, z_left, call.p, call.ignored)
        kind, what = self.watch.labels[row]
        # outputs between the check before the crossing and the crossing were computed past a
        # kink the call stepped over: compute them again up to the crossing
        samples.append(self._refill(call, t_left, t_cross, x_left, z_left))
        if not crossed:
            # the crossing was the long call's own error: a run from the check before it does not
            # cross; the run goes on from there
            return Stop(UNCONFIRMED, t_cross, x_cross, z_cross, samples)
        # rising: the watched value (a condition's left side minus its right) went from below zero
        before = float(np.asarray(self.watch.function(x_left, z_left, call.p, t_left))[row, 0])
        return Stop(kind, t_cross, x_cross, z_cross, samples, row, what, direction=1 if before <= 0 else -1,
                    together=tuple((i, self.watch.labels[i][1], d) for i, d in together))

    def _refill(self, call: Call, t_a: float, t_b: float, x_a, z_a) -> tuple:
        """The output times in (t_a, t_b] and the states there, integrated from the point at t_a."""
        times = [v for v in call.outputs if t_a < v <= t_b]
        if not times:
            return times, np.zeros((len(x_a), 0)), np.zeros((len(z_a), 0))
        xdot = self.idas.derivative(x_a, z_a, call.p, t_a)
        segment = self.idas.run(t_a, times, x_a, z_a, call.p, consistent=True,
                                step0=first_step(self.idas, x_a, xdot, t_a, t_b), xdot=xdot)
        self.tally(segment.counters)
        return times, segment.xs, segment.zs
