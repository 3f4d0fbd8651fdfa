"""The native IDAS driver as an Integrator (compiler/runtime/integrator.py): IDAS kept between
calls, restarted only where the call does not go on from where IDAS stands with the same
equations (another point, other parameters or watched rows: an event, a state-set switch, a time
event that moves the event clock); `tstop` at the call's reach; the watched rows found by IDAS's
own root finding, with direction; the outputs by dense output; the statistics read from IDAS."""
from __future__ import annotations

from dataclasses import replace
from typing import Mapping

import numpy as np

from ..checks import RUNAWAY_LIMIT, check_divergence
from ..crossings import proposing_rows, root_directions
from ..errors import SimulationFailed
from ..idas import idas_reason
from ..integrator import FAILED, REACHED, Call, Stop, Tally
from ..model import CompiledModel
from ..state_sets import degraded_level
from ..switching import all_outputs
from ..watches import Watch

from . import library

# CasADi IDAS options (runtime/idas.integrator_options and a caller's integrator_options) that
# the native driver honours, and the ones that do not apply to it: it starts every call from a
# consistent point with der(x) from the model, and factorizes with dense LU
HONOURED = {"reltol", "abstol", "abstolv", "max_num_steps", "suppress_algebraic", "max_step_size",
            "max_multistep_order", "step0"}
NOT_APPLICABLE = {"calc_ic", "init_xdot", "disable_internal_warnings", "show_eval_warnings",
                  "linear_solver"}


# Newton steps at most where the algebraic equations are solved in C (algebraic_solution): from
# a point IDAS converged to its tolerance, or the last state set's values, 2-3 reach round-off
SOLVE_STEPS = 8

# how far of the way to a failure a state-set model's call is repeated (_failed); to where IDAS
# failed, the repeated call (with tstop there) failed too (the Test Set's transistor amplifier
# written with its diode currents, tests/structure/test_models.py)
RETRY_REACH = 0.9


# The smallest absolute tolerance (times the nominal value) of an algebraic unknown out of IDAS's
# error test (suppress_algebraic), where its tolerance only weighs IDAS's Newton convergence test.
# Below it the test asks for less than the unknown's round-off: in the Test Set's transistor
# amplifier after a state-set switch (rtol 5e-14 = ROUNDOFF_RTOL, atol alike) der(y7) is computed
# from node voltages rounded to 1e-16 relative through C5 = 5e-6, and the Newton corrections
# stalled at 5-40 weights (0.33 asked) on steps of 3e-6 s: IDA_CONV_FAIL at t = 0.0131 (rtol
# 5e-13, 1.1e-12, 1.25e-12 over 0.02 s; 1e-12 passed), and at t = 0.0226 over 0.2 s at 1e-12.
# CasADi's IDAS passed on the same state set (why is not isolated). With the floor all
# pass, the node voltages to the same digits as CasADi's (docs/numerics.md, "Tight tolerances
# on both paths"). The states keep the user's atol, and every unknown keeps rtol * |value|.
# At every restart the driver raises each further, to the round-off with which the point's
# algebraic equations determine it (compiler/native/dyad_idas_floors.c): a fixed floor cannot
# know that the transistor amplifier's der(y7) is solved through a pivot of 2.2e-4 in one state
# set (docs/numerics.md, "The transistor amplifier near rtol 1e-10 on the native path").
NEWTON_ATOL_FLOOR = 1e-12


def newton_atol(model: CompiledModel, atol: np.ndarray) -> np.ndarray:
    """`atol` (states then algebraic unknowns) with each algebraic unknown's raised to
    NEWTON_ATOL_FLOOR times its nominal value, for a run whose algebraic unknowns are out of the
    error test."""
    nx = len(model.state_names)
    floor = np.array([NEWTON_ATOL_FLOOR * abs(model.nominals.get(name, 1.0)) for name in model.algebraic_names])
    raised = np.array(atol, dtype=float)
    raised[nx:] = np.maximum(raised[nx:], floor)
    return raised


def unhonoured_options(options: Mapping) -> list[str]:
    """The IDAS options the native driver cannot honour (their run goes to CasADi's IDAS)."""
    return sorted(set(options) - HONOURED - NOT_APPLICABLE)


class NativeIdas:
    """Integrator on the native driver for one model (its C library) and one set of options."""
    locates_crossings = True
    name = "native"
    why = None

    def __init__(self, model: CompiledModel, options: Mapping, watch: Watch | None, tally: Tally,
                 watch_atol: float):
        self.model, self.watch, self.tally = model, watch, tally
        nx, nz, npar = model.sizes
        nrows = 0 if watch is None else len(watch.labels)
        self.driver = library.Driver(model.native_library, nx, nz, npar, nrows)
        atol = np.asarray(options.get("abstolv", [options.get("abstol", 1e-8)] * (nx + nz)), dtype=float)
        if options.get("suppress_algebraic", False):
            atol = newton_atol(model, atol)
        directions = root_directions(watch) if watch is not None else np.zeros(0, dtype=int)
        sides = zero_sides(watch) if watch is not None else np.zeros(0, dtype=int)
        proposes = np.zeros(nrows, dtype=int)
        proposes[proposing_rows(model, watch) if watch is not None else []] = 1
        self.level_rows = {what: i for i, (kind, what) in enumerate(watch.labels if watch else ())
                           if kind == "state set"}
        flag = self.driver.setup(float(options.get("reltol", 1e-6)), atol,
                                 bool(options.get("suppress_algebraic", False)),
                                 float(options.get("max_step_size", 0.0)),
                                 int(options.get("max_multistep_order", 0)), directions, sides,
                                 proposes, watch_atol)
        if flag:
            raise RuntimeError(f"IDAS set-up failed: {_flag_name(flag)} ({self.driver.message()})")
        self.max_steps = int(options.get("max_num_steps", 100000))
        self.step0 = float(options.get("step0", 0.0))
        self.nrows = nrows
        self.all_active = np.ones(nrows, dtype=np.intc)      # the rows of a call that ignores none
        self.all_active.setflags(write=False)
        self.at: tuple | None = None        # (t, x, z, p, active) where IDAS stands
        self.counted = np.zeros(len(library.COUNTER_NAMES), dtype=np.int_)

    def advance(self, call: Call) -> Stop:
        active = self.all_active
        if call.ignored:
            active = active.copy()
            active[sorted(call.ignored)] = 0
        if call.fresh or not self._goes_on(call, active):
            flag = self.driver.restart(call.t0, call.x0, call.z0, call.p, active,
                                       call.step0 if call.step0 else self.step0)
            self.counted[:] = 0
            if flag:
                return self._failed(call, flag, call.t0)
        samples = []
        while True:
            done = sum(len(times) for times, _, _ in samples)
            flag, k, xs, zs, t, x, z, row, direction = self.driver.advance(
                call.reach, call.outputs[done:], RUNAWAY_LIMIT * call.scale, self.max_steps)
            samples.append((call.outputs[done:done + k], xs, zs))
            if flag != library.PROPOSED:
                break
            # a multi-row level proposes a switch (its indicator is not positive): taken where its
            # pivot has degraded at this point, else IDAS steps on with its history
            polished = self.algebraic_solution(t, x, z, call.p)
            settled = polished is not None
            z_out = polished if settled else z
            outputs = all_outputs(self.model, x, z_out, call.p, t, settled)
            level = degraded_level(self.model.state_sets, outputs)
            if level in self.level_rows:
                self._tally()
                self.at = None
                return Stop("state set", t, x, z_out, samples, self.level_rows[level], level, settled=settled,
                            outputs=outputs)
        self._tally()
        if flag == library.ROOT and call.last and t >= call.reach:
            # a watched row on its zero at the run's stop (IDAS reports a root at tstop where the
            # row lands on zero there, time % 2 < 1 at t = 5): the run ends with no crossing
            flag = library.REACHED
        if flag == library.REACHED:
            self.at = (call.reach, x, z, call.p, active)
            return Stop(REACHED, call.reach, x, z, samples)
        self.at = None
        if flag == library.ROOT:
            kind, what = self.watch.labels[row]
            polished = self.algebraic_solution(t, x, z, call.p)
            return Stop(kind, t, x, z if polished is None else polished, samples, row, what,
                        direction=direction, settled=polished is not None)
        if flag == library.INTERRUPTED:
            raise KeyboardInterrupt          # Ctrl-C, taken by the driver while IDAS stepped
        if flag == library.RUNAWAY:
            check_divergence(self.model, np.array([t]), x.reshape(-1, 1), call.scale)
        return self._failed(call, flag, t)

    def algebraic_solution(self, t: float, x, z, p) -> np.ndarray | None:
        """z solving the model's algebraic equations at (t, x) to round-off, by Newton steps in C
        from `z`; None where they do not get there (no finite value, a singular Jacobian, no
        convergence in SOLVE_STEPS): the caller's own search takes over."""
        outcome, solved = self.driver.solve_algebraic(t, x, z, p, SOLVE_STEPS)
        return solved if outcome == 1 else None

    def _goes_on(self, call: Call, active: np.ndarray) -> bool:
        """Whether IDAS stands where the call starts, with the same equations: then it steps on
        with its step history instead of a cold restart."""
        if self.at is None:
            return False
        t, x, z, p, was_active = self.at
        return (t == call.t0 and np.array_equal(x, call.x0) and np.array_equal(z, call.z0)
                and np.array_equal(p, call.p) and np.array_equal(was_active, active))

    def _tally(self) -> None:
        now = self.driver.counters()
        self.tally(dict(zip(library.COUNTER_NAMES, (now - self.counted).tolist())))
        self.counted = now

    def _failed(self, call: Call, flag: int, t: float) -> Stop:
        self.at = None
        # IDAS's message without the name of the function that wrote it, explained as on CasADi's
        said = self.driver.message().split(": ", 1)[-1]
        reason = idas_reason(f'returned "{_flag_name(flag)}"', said)
        failure = SimulationFailed(f"simulation of {self.model.name} failed at t = {t:.10g}: {reason}",
                                   float(t), reason)
        # a state-set model: the call again, cut short of the failure (RETRY_REACH of the way),
        # where the run looks for the state set pivoting prefers before going into the failure
        # again (stops.on_reached), as CasADi's IDAS runs do from the check before a failure
        retry = replace(call, reach=call.t0 + RETRY_REACH * (t - call.t0), retry=True) \
            if self.model.state_sets and not call.retry and call.t0 < t <= call.reach else None
        return Stop(FAILED, call.t0, call.x0, call.z0, failure=failure, retry=retry)


# a relation's operator in its event label (str of the sympy relational, compiler/lower/events.py)
# -> the side of its zero function g = lhs - rhs that g = 0 shares the relation's value with
_ZERO_SIDE = {">": -1, ">=": 1, "<": 1, "<=": -1}


def zero_sides(watch: Watch) -> np.ndarray:
    """The side (+1, -1) each watched row's exact zero counts as: for an event row of a relation,
    the side where the relation has the value it has at zero, so that leaving zero towards the
    other value is a sign change IDAS finds (`x < 0` from x = 0 falling); -1 for a bound or a
    state set (zero is outside: positive inside) and for kinks without a relation (min, abs)."""
    sides = []
    for kind, what in watch.labels:
        words = str(what).split(" ") if kind == "event" else []
        operators = [w for w in words if w in _ZERO_SIDE]
        sides.append(_ZERO_SIDE[operators[0]] if len(operators) == 1 else -1)
    return np.array(sides, dtype=int)


def _flag_name(flag: int) -> str:
    return library.IDA_FLAGS.get(flag, f"IDAS flag {flag}")
