"""The result of a run: the output grid, the named signals on it, the events and state-set switches
that happened, and the solver's counters."""
from __future__ import annotations

import os
from typing import Sequence

import numpy as np

from .errors import ModelInputError, did_you_mean


class Result:
    """`result["name"]` is a signal on `result.time`; `events` lists located state events as
    {"time", "event", "direction"} (direction "rising" or "falling": the event condition's left
    side minus its right side crossed zero upward or downward); `switches` lists state-set
    switches as {"time", "from", "to", "quality"}; `parameters` is every parameter's value in the
    run (defaults with the caller's overrides, bound parameters re-derived)."""

    def __init__(self, time: np.ndarray, names: Sequence[str], values: np.ndarray,
                 stats: dict | None = None, model_name: str = "", *,
                 units: dict | None = None, events: list | None = None, switches: list | None = None,
                 parameters: dict | None = None):
        self.time = np.asarray(time, dtype=float)
        self.names = list(names)
        self.values = np.asarray(values, dtype=float).reshape(len(self.names), len(self.time))
        self.stats = dict(stats or {})
        self.model_name = model_name
        self.units = dict(units or {})
        self.events = list(events or [])
        self.switches = list(switches or [])
        self.parameters = dict(parameters or {})
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

    def write(self, path: str | os.PathLike, names: Sequence[str] | None = None) -> list[str]:
        """Write time and the chosen signals in the format the extension names (.csv, .parquet,
        .mat, .npz), atomically: no partial file on failure. The run's parameters go into the
        file's metadata, for CSV into a sidecar FILE.json (the CSV stays a plain table). Returns
        the paths written."""
        from .writers import sidecar_path, write_sidecar, write_table
        columns = self.columns(names)
        units = {n: self.units.get(n, "") for n in columns}
        write_table(path, self.time, columns, units, parameters=self.parameters)
        sidecar = sidecar_path(path)
        if sidecar is not None:
            write_sidecar(sidecar, units, self.parameters, self.model_name)
        return [os.fspath(path)] + ([sidecar] if sidecar else [])

    def to_csv(self, path: str | os.PathLike, names: Sequence[str] | None = None) -> list[str]:
        if os.path.splitext(os.fspath(path))[1].lower() != ".csv":
            raise ModelInputError(f"to_csv writes .csv files, not {os.fspath(path)!r}: use write()")
        return self.write(path, names)

    def write_events(self, path: str | os.PathLike) -> None:
        """The located events as CSV: `time,event,direction`, one row per event in time order."""
        from .writers import write_events
        write_events(path, self.events)

    def to_pandas(self, names: Sequence[str] | None = None):
        """A pandas DataFrame of the chosen signals (default: all) indexed by `time`;
        `attrs["units"]` maps each column to its unit (as the Parquet field metadata does),
        `attrs["parameters"]` holds the run's parameter values."""
        try:
            import pandas
        except ImportError:
            raise ModelInputError("Result.to_pandas needs pandas: pip install 'dyadc[io]' "
                                  "(or pip install pandas)") from None
        columns = self.columns(names)
        frame = pandas.DataFrame(columns, index=pandas.Index(self.time, name="time"))
        frame.attrs["units"] = {n: self.units[n] for n in columns if self.units.get(n)}
        frame.attrs["parameters"] = dict(self.parameters)
        return frame

    def plot(self, path: str | os.PathLike | None = None, names: Sequence[str] | None = None,
             title: str | None = None):
        """One subplot per unit; never changes the user's matplotlib backend. Returns the Figure,
        written to `path` when one is given (without one, for a notebook to show)."""
        from .plotting import plot_signals
        columns = self.columns(names)
        return plot_signals(path, self.time, columns, self.units, title or self.model_name)
