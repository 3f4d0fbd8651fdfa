"""The Integrator interface: what the run loop (run_loop.py) asks of an integrator, and what it
gets back. The loop says where a call starts, how far it may go and which output times it wants;
the integrator goes there and says where and why it stopped (docs/runtime.md, "The Integrator
interface"). Implementations: `SampledIdas` (sampled_idas.py, IDAS through CasADi, crossings found
at check times after each call) and `NativeIdas` (compiler/runtime/native/, IDAS's own root finding).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Mapping, Protocol, Sequence

import numpy as np

from .errors import SimulationFailed
from .watches import Watch

# IDAS's statistics by CasADi's name -> the name in Result.stats
COUNTERS = {"nsteps": "steps", "nfevals": "residual_evaluations", "n_call_jacF": "jacobian_evaluations",
            "nlinsetups": "linear_solver_setups", "netfails": "error_test_failures",
            "nniters": "newton_iterations", "nncfails": "newton_convergence_failures"}

# Why a call stopped (Stop.kind); a crossing stops with its watch row's kind ("event", "bound",
# "state set": Watch.labels).
REACHED = "reached"              # at Call.reach, no crossing before it
UNCONFIRMED = "unconfirmed"      # a crossing seen by the call vanished when looked at closely
FAILED = "failed"                # the integrator failed; the run is where the call started


@dataclass(frozen=True)
class Call:
    """One call: from (t0, x0, z0) with parameters p (held over the call) to `reach` at the
    latest (a time event, the stop, or less), with the states at the `outputs` times (the output
    grid in (t0, reach]). It ends early at the first crossing of a watched row other than
    `ignored` ones (a row that reaches its zero at the run's stop, `last`, has no crossing: the
    relation has no value after it). After every point it passes, the states are checked against
    `scale` (checks.check_divergence). A call that starts at a breakpoint the caller gave (an
    input's kink) is `fresh`: the integrator restarts there, without the history from before the
    kink. `horizon`, `step0`, `checks` and `retry` serve an integrator that finds crossings after
    a call (Integrator.locates_crossings False), and are None otherwise."""
    t0: float
    x0: np.ndarray
    z0: np.ndarray
    p: np.ndarray
    reach: float
    outputs: np.ndarray                 # ascending float64 (segments.output_times)
    scale: np.ndarray
    ignored: frozenset[int] = frozenset()
    horizon: float | None = None        # how far calls of a state-set model reach now
    step0: float | None = None          # the first step; None: the integrator's own rule
    checks: tuple[float, ...] | None = None   # where watched rows are sampled; None: its own
    retry: bool = False                 # repeats a failed call, cut before the failure
    last: bool = False                  # reach is the run's stop: nothing comes after it
    fresh: bool = False                 # starts at a caller's breakpoint: a cold restart there


@dataclass
class Stop:
    """Where a call stopped and why. (t, x, z) is where the run goes on from: `reach`, the
    crossing, or the call's start when it failed. `samples` are (times, xs, zs) chunks of the
    output times passed, in order. A crossing of watch row `row` has `what`, the second half of
    its label. A failure has `failure` and, where the integrator can tell, `retry`: the call cut
    before the failure, which a watched crossing before the failure would show in."""
    kind: str
    t: float
    x: np.ndarray
    z: np.ndarray
    samples: list[tuple[Sequence[float], np.ndarray, np.ndarray]] = field(default_factory=list)
    row: int | None = None
    what: object = None
    failure: SimulationFailed | None = None
    retry: Call | None = None
    horizon: float | None = None        # reached: how far the next call should reach (predicted)
    direction: int = 0                  # a crossing: +1 its watched value rose through zero, -1 fell
    # an event: the other event rows that crossed at the same instant, (row, what, direction)
    together: tuple = ()
    # z solves the algebraic equations at (t, x) to round-off already (the integrator polished
    # it): the outputs there need no Newton steps of polishing (switching.all_outputs)
    settled: bool = False
    # every output at (t, x, z) where the integrator computed them already (a state set's switch
    # proposed by its indicator and confirmed on them): the run does not compute them again
    outputs: np.ndarray | None = None


class Integrator(Protocol):
    """An integrator of one model (one state set) with one set of options, made for one run with
    the watched functions and a `tally(counters)` callback that it calls once per solver run
    (RunState.integrator)."""
    watch: Watch | None
    # True: crossings are found while integrating (root finding), so every call may reach the
    # segment's end; False: after a call, so the loop shortens calls (event_horizon.py, horizons)
    locates_crossings: bool
    # why this integrator runs where another was the first choice (Result.stats["integrator_why"])
    why: str | None

    def advance(self, call: Call) -> Stop: ...


Tally = Callable[[Mapping], None]
