"""What a run is asked to do: span, output grid, tolerances, parameter overrides; validated once,
before anything is computed."""
from __future__ import annotations

import dataclasses
import math
import sys
from dataclasses import dataclass
from typing import Callable, Mapping, Sequence

import numpy as np

from .errors import ModelInputError, did_you_mean

MAX_OUTPUT_POINTS = 10_000_000
SMALLEST_TOLERANCE = 1e-100   # below this a tolerance means nothing to IDAS (atol 1e-300 never ends)
# the integrators a run can ask for by name (native/choice.py makes them)
CHOICES = ("casadi", "native")
SHORTEST_SPAN = 1e-12         # relative: a span below this is round-off


@dataclass(frozen=True)
class SimulationOptions:
    stop: float
    start: float = 0.0
    points: int = 501
    saveat: Sequence[float] | None = None       # output times instead of `points` evenly spaced
    rtol: float = 1e-6
    atol: float | Mapping[str, float] = 1e-6    # one value, or per unknown with "*" as the default
    max_steps: int = 100000                     # IDAS steps between two output times
    max_step: float | None = None               # largest IDAS step size
    params: Mapping[str, float] | None = None
    breakpoints: Sequence[float] | None = None  # more time events, besides the model's own
    integrator_options: Mapping | None = None   # passed to CasADi's IDAS interface as they are
    progress: bool | None = None                # None: a bar on a terminal for long runs
    signals: Sequence[str] | None = None        # the outputs to compute (None: every output)
    # a declared min/max left during the run: "warn" (Dyad's and Modelica's reading: bounds are
    # metadata, checked) goes on with a warning, "error" stops the run there
    bounds: str = "warn"
    # what makes the run's integrators: "native", "casadi", a maker
    # make_integrator(model, idas options, watch, tally) -> Integrator (integrator.py), or None:
    # $DYADC_INTEGRATOR, else the native IDAS driver where it can run the model and CasADi's IDAS
    # where not, the reason reported (native/choice.py: the one choice every caller of simulate gets)
    integrator: Callable | str | None = None

    def validated(self) -> "SimulationOptions":
        start, stop = _finite("start", self.start), _finite("stop", self.stop)
        if not stop > start:
            raise ModelInputError(f"stop time {stop:g} must be after start time {start:g}")
        if stop - start <= SHORTEST_SPAN * max(1.0, abs(start), abs(stop)):
            raise ModelInputError(f"the span from {start:g} to {stop:g} is shorter than round-off")
        _positive("rtol", self.rtol)
        if isinstance(self.atol, Mapping):
            for name, value in self.atol.items():
                _positive(f"atol for '{name}'", value)
        else:
            _positive("atol", self.atol)
        if self.max_step is not None:
            _positive("max_step", self.max_step)
        if self.bounds not in ("warn", "error"):
            raise ModelInputError(f"bounds must be 'warn' or 'error', got {self.bounds!r}")
        if self.integrator is not None and not callable(self.integrator) and self.integrator not in CHOICES:
            raise ModelInputError(f"integrator must be {' or '.join(map(repr, CHOICES))} or make "
                                  f"integrators (a callable, e.g. compiler.runtime.native.make_integrator), "
                                  f"got {self.integrator!r}")
        if int(self.max_steps) < 1:
            raise ModelInputError(f"max_steps must be at least 1, got {self.max_steps}")
        if self.saveat is None:
            if int(self.points) < 2:
                raise ModelInputError(f"points must be at least 2, got {self.points}")
            if int(self.points) > MAX_OUTPUT_POINTS:
                raise ModelInputError(f"{int(self.points)} output points is more than the limit of "
                                      f"{MAX_OUTPUT_POINTS}")
        else:
            saveat = np.asarray([float(s) for s in self.saveat], dtype=float)
            if saveat.size == 0:
                raise ModelInputError("saveat is empty")
            if saveat.size > MAX_OUTPUT_POINTS:
                raise ModelInputError(f"{saveat.size} output times is more than the limit of "
                                      f"{MAX_OUTPUT_POINTS}")
            if not np.all(np.isfinite(saveat)):
                raise ModelInputError("saveat times must be finite numbers")
            if saveat.min() < start or saveat.max() > stop:
                raise ModelInputError(f"saveat times must lie in [start, stop] = [{start:g}, {stop:g}]")
            stop = float(saveat.max())          # the run ends at the last time asked for
            if not stop > start:
                raise ModelInputError("saveat must hold a time after the start")
        for name, value in (self.params or {}).items():
            try:
                number = float(value)
            except (TypeError, ValueError):
                raise ModelInputError(f"parameter '{name}': value {value!r} is not a number") from None
            if not math.isfinite(number):
                raise ModelInputError(f"parameter '{name}': value {value!r} is not finite")
        return dataclasses.replace(self, start=start, stop=stop)

    def grid(self) -> np.ndarray:
        if self.saveat is not None:
            grid = np.unique(np.asarray([float(s) for s in self.saveat], dtype=float))
            if grid[0] > self.start:
                grid = np.concatenate([[self.start], grid])
            return grid
        return np.linspace(self.start, self.stop, int(self.points))

    def chosen_signals(self, available: Sequence[str]) -> list[str]:
        """The signals a run computes: `signals` in the order given (duplicates and "time"
        dropped), or every one of `available`. An unknown name is an error with a suggestion."""
        if self.signals is None:
            return list(available)
        if isinstance(self.signals, str):
            raise ModelInputError(f"signals must be a list of names, not the string {self.signals!r}")
        known = set(available)
        chosen: list[str] = []
        for name in self.signals:
            if not isinstance(name, str):
                raise ModelInputError(f"signals must be names, got {name!r}")
            if name == "time" or name in chosen:
                continue
            if name not in known:
                raise ModelInputError(f"unknown signal '{name}'" + did_you_mean(name, list(available)))
            chosen.append(name)
        return chosen

    def show_progress(self) -> bool:
        return sys.stderr.isatty() if self.progress is None else bool(self.progress)

    def idas_options(self) -> dict:
        extra = dict(self.integrator_options or {})
        if self.max_step is not None:
            extra.setdefault("max_step_size", float(self.max_step))
        return extra


def _finite(name: str, value) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ModelInputError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(number):
        raise ModelInputError(f"{name} must be finite, got {value!r}")
    return number


def _positive(name: str, value) -> float:
    number = _finite(name, value)
    if not number > 0:
        raise ModelInputError(f"{name} must be positive, got {value!r}")
    if number < SMALLEST_TOLERANCE and name != "max_step":
        raise ModelInputError(f"{name} {value!r} is below {SMALLEST_TOLERANCE:g}: no solver resolves it")
    return number
