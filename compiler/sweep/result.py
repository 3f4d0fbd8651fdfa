"""The outcome of a sweep as tidy tables: trajectories (one row per sample and output time) and
samples (one row per sample: status, failure reason and time, run time, metrics)."""
from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

from compiler.errors import DyadError
from compiler.sweep.design import Design
from compiler.sweep.worker import Job, Outcome
from compiler.sweep.writers import sibling, write_table


class SweepResult:
    def __init__(self, model_name: str, design: Design, job: Job, outcomes: Mapping[int, Outcome],
                 complete: bool = True, stats: dict | None = None, units: Mapping[str, str] | None = None):
        self.model_name = model_name
        self.units = {"time": "s", **dict(units or {})}      # declared units of parameters and signals
        self.design = design
        self.job = job
        self.outcomes = dict(sorted(outcomes.items()))
        self.complete = complete
        self.stats = dict(stats or {})

    # -- what happened --------------------------------------------------------------------------
    @property
    def parameters(self) -> tuple[str, ...]:
        return self.design.names

    @property
    def variables(self) -> tuple[str, ...]:
        return self.job.variables

    @property
    def metric_labels(self) -> tuple[str, ...]:
        return tuple(m.label for m in self.job.metrics)

    @property
    def succeeded(self) -> list[Outcome]:
        return [o for o in self.outcomes.values() if o.ok]

    @property
    def failed(self) -> list[Outcome]:
        return [o for o in self.outcomes.values() if not o.ok]

    def __len__(self) -> int:
        return len(self.outcomes)

    def parameter_values(self, sample: int) -> dict[str, float]:
        return {n: float(v) for n, v in zip(self.design.names, self.design.values[sample])}

    def signal(self, name: str) -> tuple[np.ndarray, np.ndarray, list[int]]:
        """(time, values[k, t], samples): one row per successful sample."""
        if name not in self.job.variables:
            raise DyadError(f"`{name}` was not recorded in this sweep",
                            hint=f"recorded: {', '.join(self.job.variables) or 'none (use --vars)'}")
        done = self.succeeded
        if not done:
            return np.zeros(0), np.zeros((0, 0)), []
        return done[0].time, np.vstack([o.values[name] for o in done]), [o.sample for o in done]

    def metric(self, label: str) -> tuple[np.ndarray, list[int]]:
        """(values, samples) of one metric over every finished sample (NaN where it failed)."""
        if label not in self.metric_labels:
            raise DyadError(f"no metric `{label}` in this sweep",
                            hint=f"metrics: {', '.join(self.metric_labels) or 'none (use --metrics)'}")
        samples = list(self.outcomes)
        return np.array([self.outcomes[s].metrics.get(label, math.nan) for s in samples]), samples

    # -- tables ---------------------------------------------------------------------------------
    def trajectories(self) -> dict[str, np.ndarray]:
        """Columns `sample`, each swept parameter, `time`, each recorded variable."""
        done = self.succeeded
        lengths = [len(o.time) for o in done]
        sample = np.repeat(np.array([o.sample for o in done], dtype=np.int64), lengths)
        columns: dict[str, np.ndarray] = {"sample": sample}
        for j, name in enumerate(self.design.names):
            columns[name] = self.design.values[sample, j] if len(sample) else np.zeros(0)
        columns["time"] = np.concatenate([o.time for o in done]) if done else np.zeros(0)
        for name in self.job.variables:
            columns[name] = np.concatenate([o.values[name] for o in done]) if done else np.zeros(0)
        return columns

    def samples(self) -> dict[str, np.ndarray | list]:
        """One row per finished sample: parameters, `status`, `reason`, `failed_at`, `seconds`,
        `worker` and each metric."""
        rows = list(self.outcomes.values())
        index = np.array([o.sample for o in rows], dtype=np.int64)
        columns: dict[str, np.ndarray | list] = {"sample": index}
        for j, name in enumerate(self.design.names):
            columns[name] = self.design.values[index, j] if len(index) else np.zeros(0)
        columns["status"] = ["ok" if o.ok else "failed" for o in rows]
        columns["reason"] = [o.reason or "" for o in rows]
        columns["failed_at"] = np.array([math.nan if o.time_reached is None else o.time_reached
                                         for o in rows], dtype=float)
        columns["seconds"] = np.array([o.seconds for o in rows], dtype=float)
        columns["worker"] = [o.worker for o in rows]
        for label in self.metric_labels:
            columns[label] = np.array([o.metrics.get(label, math.nan) for o in rows], dtype=float)
        return columns

    def to_pandas(self, table: str = "trajectories"):
        """A pandas DataFrame of `trajectories()` or `samples()` (pandas is imported only here)."""
        try:
            import pandas as pd
        except ImportError:
            raise DyadError("SweepResult.to_pandas needs pandas, which is not installed",
                            hint="pip install pandas, or use .trajectories() / .samples() (numpy columns)") \
                from None
        if table not in ("trajectories", "samples"):
            raise DyadError(f"unknown table `{table}`", hint="'trajectories' or 'samples'")
        return pd.DataFrame(self.trajectories() if table == "trajectories" else self.samples())

    def write(self, path: str | os.PathLike) -> tuple[Path, Path]:
        """Trajectories to `path`, the sample table beside it (`NAME.samples.EXT`)."""
        return (write_table(self.trajectories(), path, self.units),
                write_table(self.samples(), sibling(path, "samples"), self.units))

    def plot(self, path: str | os.PathLike, signals: Sequence[str] | None = None,
             metrics: Sequence[str] | None = None) -> Path:
        """Fan charts of `signals` (default: the first three recorded) over time and scatters of
        `metrics` (default: all) against the swept parameters; matplotlib's Figure, no pyplot."""
        from compiler.sweep.plot import summary_figure, save_figure
        figure = summary_figure(self, list(signals) if signals is not None else list(self.variables[:3]),
                                list(metrics) if metrics is not None else list(self.metric_labels))
        return save_figure(figure, path)

    def summary(self) -> str:
        done, failed = len(self.outcomes), len(self.failed)
        total = len(self.design)
        head = (f"{self.model_name}: {done - failed} of {total} samples succeeded"
                + (f", {failed} failed" if failed else "")
                + ("" if self.complete else f", {total - done} not run (interrupted)"))
        lines = [head]
        for o in self.failed[:10]:
            where = "" if o.time_reached is None else f" at t = {o.time_reached:.6g}"
            values = ", ".join(f"{n}={v:g}" for n, v in self.parameter_values(o.sample).items())
            lines.append(f"  sample {o.sample} ({values}) failed{where}: {o.reason}")
        if failed > 10:
            lines.append(f"  ... and {failed - 10} more (see the samples table)")
        return "\n".join(lines)
