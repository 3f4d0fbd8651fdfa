"""What can go wrong in a run, as exceptions that carry the time and the reason, and the one
"did you mean" helper of the project."""
from __future__ import annotations

import difflib
from typing import Iterable


class SimulationFailed(Exception):
    """The run could not continue. `time_reached` is the last time it got to; `variable` names the
    signal that caused it, where one did (a bound, a non-finite or runaway value)."""

    def __init__(self, message: str, time_reached: float | None = None, reason: str | None = None,
                 variable: str | None = None):
        super().__init__(message)
        self.time_reached = time_reached
        self.reason = reason
        self.variable = variable
        self.partial = None          # the Result up to the last output time reached, where the
                                     # driver had one (written only when the user asks for it)


class InitializationFailed(SimulationFailed):
    """No consistent initial point. `worst` lists (residual index, value, label), largest first."""

    def __init__(self, message: str, time_reached: float, worst: list[tuple[int, float, str]]):
        super().__init__(message, time_reached, "inconsistent or unsolvable initial conditions")
        self.worst = worst


class SimulationInterrupted(KeyboardInterrupt):
    """The user pressed Ctrl-C; `time_reached` is where the run was. A KeyboardInterrupt, so that
    whoever handles Ctrl-C (the CLI, a sweep) handles it as one."""

    def __init__(self, message: str, time_reached: float | None = None, reason: str | None = None):
        super().__init__(message)
        self.time_reached = time_reached
        self.reason = reason


class ModelInputError(ValueError):
    """A bad request from the user of a compiled model (unknown parameter or output name, ...)."""


def did_you_mean(name: str, choices: Iterable[str]) -> str:
    """' (did you mean 'a', 'b'?)' for the closest choices, '' when none is close."""
    close = difflib.get_close_matches(name, list(choices), n=3, cutoff=0.5)
    return f" (did you mean {', '.join(repr(c) for c in close)}?)" if close else ""
