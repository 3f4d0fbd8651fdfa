"""The summary picture of a sweep: a fan chart of each chosen signal over time (median, 25-75 % and
5-95 % bands, the extremes dotted) and a scatter of each metric against each swept parameter.
Drawn on a matplotlib.figure.Figure: pyplot and the process's backend are never touched."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Sequence

import numpy as np

from compiler.errors import DyadError
from compiler.sweep.writers import atomic_write

MAX_SIGNALS = 3
MAX_SCATTERS = 4


def summary_figure(result, signals: Sequence[str], metrics: Sequence[str]):
    """Fan charts of `signals` in the first row; below, each metric against each swept parameter
    (at most MAX_SCATTERS panels, metrics first)."""
    from matplotlib.figure import Figure

    signals = list(signals)[:MAX_SIGNALS]
    pairs = [(m, p) for m in metrics for p in result.parameters][:MAX_SCATTERS]
    rows = [r for r, wanted in (("fan", signals), ("scatter", pairs)) if wanted]
    if not rows:
        raise DyadError("nothing to plot: the sweep recorded no signals and no metric",
                        hint="add --vars NAME ... or --metrics EXPR")
    columns = max(len(signals) if "fan" in rows else 1, len(pairs) if "scatter" in rows else 1)
    figure = Figure(figsize=(4.2 * columns, 3.4 * len(rows)), layout="constrained")
    grid = figure.add_gridspec(len(rows), columns)
    row = 0
    if "fan" in rows:
        for k, name in enumerate(signals):
            _fan(figure.add_subplot(grid[row, k]), result, name)
        row += 1
    if "scatter" in rows:
        for k, (metric, parameter) in enumerate(pairs):
            _scatter(figure.add_subplot(grid[row, k]), result, metric, parameter)
    failed = len(result.failed)
    figure.suptitle(f"{result.model_name.split('.')[-1]}: {len(result.outcomes)} samples"
                    + (f", {failed} failed (not in the fan charts)" if failed else ""), fontsize="medium")
    return figure


def _fan(ax, result, name: str) -> None:
    time, values, _ = result.signal(name)
    if len(values):
        low, q25, median, q75, high = np.percentile(values, [5, 25, 50, 75, 95], axis=0)
        ax.fill_between(time, low, high, color="tab:blue", alpha=0.18, lw=0, label="5-95 %")
        ax.fill_between(time, q25, q75, color="tab:blue", alpha=0.35, lw=0, label="25-75 %")
        ax.plot(time, median, color="tab:blue", lw=1.4, label="median")
        ax.plot(time, values.min(axis=0), color="tab:blue", lw=0.6, ls=":", label="min / max")
        ax.plot(time, values.max(axis=0), color="tab:blue", lw=0.6, ls=":")
        ax.legend(fontsize="x-small", loc="best")
    ax.set_title(name, fontsize="small")
    ax.set_xlabel("time [s]")
    ax.grid(True, alpha=0.3)


def _scatter(ax, result, metric: str, parameter: str) -> None:
    values, samples = result.metric(metric)
    j = list(result.parameters).index(parameter)
    x = result.design.values[samples, j] if samples else np.zeros(0)
    finite = np.isfinite(values)
    ax.scatter(x[finite], values[finite], s=14, color="tab:orange", edgecolor="k", linewidth=0.3,
               label="sample")
    if (~finite).any():
        bottom = np.nanmin(values) if finite.any() else 0.0
        ax.scatter(x[~finite], np.full((~finite).sum(), bottom), marker="x", color="tab:red",
                   label="failed")
        ax.legend(fontsize="x-small", loc="best")
    ax.set_xlabel(parameter)
    ax.set_ylabel(metric)
    ax.grid(True, alpha=0.3)


def save_figure(figure, path: str | os.PathLike) -> Path:
    path = Path(path)
    form = path.suffix.lstrip(".").lower() or "png"
    atomic_write(path, lambda tmp: figure.savefig(tmp, format=form, dpi=110))
    return path
