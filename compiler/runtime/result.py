"""The result of a run: the output grid, the named signals on it, the events and state-set switches
that happened, and the solver's counters."""
from __future__ import annotations

import os
from typing import Sequence

import numpy as np

from .errors import ModelInputError, did_you_mean


class Result:
    """`result["name"]` is a signal on `result.time`; `events` lists located state events as
    {"time", "event"}; `switches` lists state-set switches as {"time", "from", "to", "quality"}."""

    def __init__(self, time: np.ndarray, names: Sequence[str], values: np.ndarray,
                 stats: dict | None = None, model_name: str = "", *,
                 units: dict | None = None, events: list | None = None, switches: list | None = None):
        self.time = np.asarray(time, dtype=float)
        self.names = list(names)
        self.values = np.asarray(values, dtype=float).reshape(len(self.names), len(self.time))
        self.stats = dict(stats or {})
        self.model_name = model_name
        self.units = dict(units or {})
        self.events = list(events or [])
        self.switches = list(switches or [])
        self._index = {n: i for i, n in enumerate(self.names)}

    def __getitem__(self, name: str) -> np.ndarray:
        if name == "time":
            return self.time
        try:
            return self.values[self._index[name]]
        except KeyError:
            raise ModelInputError(f"no signal '{name}' in the result of {self.model_name or 'the model'}"
                                  + did_you_mean(name, self.names)) from None

    def __contains__(self, name: str) -> bool:
        return name == "time" or name in self._index

    def columns(self, names: Sequence[str] | None = None) -> dict[str, np.ndarray]:
        """The chosen signals (default: all) by name; unknown names fail with a did-you-mean."""
        chosen = self.names if names is None else [n for n in names if n != "time"]
        return {n: self[n] for n in chosen}

    def write(self, path: str | os.PathLike, names: Sequence[str] | None = None) -> None:
        """Write time and the chosen signals in the format the extension names (.csv, .parquet,
        .mat, .npz), atomically: no partial file on failure."""
        from .writers import write_table
        columns = self.columns(names)
        write_table(path, self.time, columns, {n: self.units.get(n, "") for n in columns})

    def to_csv(self, path: str | os.PathLike, names: Sequence[str] | None = None) -> None:
        if os.path.splitext(os.fspath(path))[1].lower() != ".csv":
            raise ModelInputError(f"to_csv writes .csv files, not {os.fspath(path)!r}: use write()")
        self.write(path, names)

    def plot(self, path: str | os.PathLike, names: Sequence[str] | None = None,
             title: str | None = None):
        """One subplot per unit; never changes the user's matplotlib backend. Returns the Figure."""
        from .plotting import plot_signals
        columns = self.columns(names)
        return plot_signals(path, self.time, columns, self.units, title or self.model_name)
