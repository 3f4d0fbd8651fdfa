"""The state of one run (run_loop.py): where it is, which model (state set) it integrates with
which parameters, the integrators and tolerances it uses, the samples it has collected, what
happened so far (events, switches, bounds left), and how far the calls of a model with state sets
reach."""
from __future__ import annotations

from typing import Callable, Mapping, Protocol

import numpy as np

from .checks import state_scales
from .idas import integrator_options
from .integrator import COUNTERS, Call, Integrator
from .model import CompiledModel
from .options import SimulationOptions
from .outputs import signals_at
from .sampled_idas import SampledIdas
from .segments import clock_on_switches
from .watches import build_watch

INITIAL_CHUNKS = 100             # a state-set model's first IDAS call reaches 1/100 of the span
MOST_CHUNKS = 1000               # and no call reaches less than 1/1000 of it (unless IDAS failed)
# IDAS restarts cold at every state-set switch (CasADi keeps no step history between calls), and
# each restart's low-order start-up costs accuracy: 31 restarts of the 2.3 rad pendulum's angle ODE
# at rtol 1e-8 end 10x less accurate than one run of it. From the first switch on, a run is
# therefore integrated at tolerances this much tighter (docs/numerics.md). A01 pendulum, worst
# variable, 100 s (169 switches) at rtol 1e-10: 20 -> 6.4 significant digits, 100 -> 7.1 for 1.22x
# the steps; over 20 s 1.2x the steps of 20.
SWITCHED_TOLERANCE = 100.0
# ... but never below this relative tolerance, where IDAS's error test meets round-off: A01 at
# rtol 1e-12 over 100 s gave 8.1 digits tightened to 5e-14, 7.7 at 2e-14 and 8.0 at 1e-14.
ROUNDOFF_RTOL = 5e-14


def switched_factor(rtol: float) -> float:
    """How much tighter than asked a run integrates from its first state-set switch on."""
    return max(1.0, min(SWITCHED_TOLERANCE, rtol / ROUNDOFF_RTOL))


class StateSetSwitcher(Protocol):
    """Provides the model of another state set where the current one degrades (the compiler's
    dynamic state selection). `public_names` are the signals every variant reports."""
    public_names: list[str]

    def switch(self, model: CompiledModel, values: Mapping[str, float], t: float) -> CompiledModel: ...


class RunState:
    """The state of one run: where it is, which model (state set) it integrates, what it collected.
    `make_integrator(model, idas options, watch, tally)` makes its integrators (integrator.py)."""

    def __init__(self, model: CompiledModel, options: SimulationOptions, switcher,
                 make_integrator: Callable[..., Integrator] = SampledIdas):
        self.options = options
        self.switcher = switcher
        self.make_integrator = make_integrator
        self.public = options.chosen_signals(list(switcher.public_names) if switcher is not None
                                             else list(model.output_names))
        self.grid = options.grid()
        # one point's signals contiguous (the .T of a points x signals array), as the vectorized
        # outputs are computed: storing them is a copy, not a transpose (excavator, C, 1201
        # points: finish 5.4 -> 4.0 ms)
        self.values = np.full((len(self.grid), len(self.public)), np.nan).T
        self.counters = {v: 0 for v in COUNTERS.values()}
        self.counters["segments"] = 0
        self.events: list[dict] = []
        self.parameters: dict[str, float] = {}   # the run's parameter values, by name
        self.switches: list[dict] = []
        self.bounds_left: list[dict] = []        # declared bounds left (bounds="warn")
        self.ignored: set[tuple] = set()         # watch labels no longer located (bounds warned of)
        self.integrators: dict[tuple, tuple] = {}
        self.integrator_names: set[str] = set()  # which integrators ran (Result.stats["integrator"])
        self.integrator_why: dict[str, None] = {}  # why not the first choice, in order (ordered set)
        self.parameter_vectors: dict[int, np.ndarray] = {}    # per state set, read-only
        self.pending: dict[int, tuple] = {}
        self.forced_ends: set[float] = set()     # ends of calls cut before a failure
        # how far one IDAS call reaches in a model with state sets (crossings.next_horizon)
        self.horizon = (options.stop - options.start) / INITIAL_CHUNKS
        # an indicator that hovers near zero without crossing must not shrink the calls for ever
        self.shortest_reach = (options.stop - options.start) / MOST_CHUNKS
        self.last_switch = options.start
        self.intervals: list[float] = []         # between the state-set switches so far
        self.durations: dict[tuple, float] = {}  # how long the run last stayed in each state set
        self.ends: list[float] = []              # where segments end (segments.segment_ends)
        # where the run is: the model (state set) it integrates with parameters p, the point
        # (t, x, z), the states' scales, the next output index and the next segment end
        self.model = model
        self.t = options.start
        self.p = self.x = self.z = self.scale = None
        self.k = 1
        self.end_index = 0
        self.restarts_here = 0                   # crossings in a row without time advancing
        self.live_from: float | None = None      # a call from this time evaluates relations live
        self.retry: Call | None = None           # the next call: a failed one, cut short

    def start_at(self, p: np.ndarray, x, z) -> None:
        """The run at its start: the point, the states' scales, the first output."""
        self.p, self.x, self.z = p, x, z
        self.scale = state_scales(self.model, x)
        index = [self.model.output_index(n) for n in self.public]
        self.values[:, 0] = signals_at(self.model, np.asarray(x).reshape(-1, 1), np.asarray(z).reshape(-1, 1),
                                       p, np.array([self.grid[0]]), index)[:, 0]

    def move(self, t: float, x, z) -> None:
        self.t, self.x, self.z = t, x, z

    def segment_end(self) -> float:
        return self.ends[self.end_index]

    def integrator(self, model: CompiledModel) -> Integrator:
        """The integrator of `model` for this run (tolerances tightened from the first switch on)."""
        switched = bool(self.switches)           # from the first switch on: tighter tolerances
        key = (id(model), switched)
        if key not in self.integrators:
            atol = self.options.atol
            base = float(atol.get("*", 1e-6)) if isinstance(atol, Mapping) else float(atol)
            watch = model.derived(("watch", base), lambda: build_watch(model, base))   # once per model
            factor = switched_factor(self.options.rtol) if switched else 1.0
            tightened = ({name: value / factor for name, value in atol.items()}
                         if isinstance(atol, Mapping) else atol / factor)
            opts = integrator_options(model, self.options.rtol / factor, tightened,
                                      self.options.max_steps, self.options.idas_options(), switched)
            integrator = self.make_integrator(model, opts, watch, self.add)
            self.integrator_names.add(getattr(integrator, "name", type(integrator).__name__))
            if getattr(integrator, "why", None):
                self.integrator_why.setdefault(integrator.why, None)
            self.integrators[key] = (model, integrator)
        return self.integrators[key][1]

    def store(self, model: CompiledModel, xs, zs, p, times) -> None:
        """Keep the points at the next output times (which are `times`); the outputs
        are computed at the end, in one vectorized call per state set and parameter vector
        (`finish`; the parameters are kept once per chunk, not once per point: the excavator's 211
        at 1201 points cost 5 ms to repeat and compare)."""
        n = len(times)
        if n == 0:
            return
        xs, zs, columns = np.asarray(xs)[:, :n], np.asarray(zs)[:, :n], np.arange(self.k, self.k + n)
        self.k += n
        if id(model) not in self.pending:
            self.pending[id(model)] = (model, [model.output_index(name) for name in self.public], {})
        chunks = self.pending[id(model)][2]
        for which, p_run in clock_on_switches(model, np.asarray(p, dtype=float).reshape(-1), times[:n], self.ends):
            chunks.setdefault(p_run.tobytes(), (p_run, []))[1].append((xs[:, which], zs[:, which], columns[which]))

    def finish(self) -> None:
        for model, public_index, by_parameters in self.pending.values():
            for p, chunks in by_parameters.values():
                xs, zs, columns = (np.concatenate([c[i] for c in chunks], axis=-1) for i in range(3))
                self.values[:, columns] = signals_at(model, xs, zs, p, self.grid[columns], public_index)
        self.pending = {}

    def add(self, counters: Mapping) -> None:
        for key, value in counters.items():
            self.counters[key] = self.counters.get(key, 0) + value
        self.counters["segments"] += 1
