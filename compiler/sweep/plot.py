"""The summary picture of a sweep: each chosen signal over time, for a grid one line per grid value
(labelled with it), for random samples a fan chart (median, 25-75 % and 5-95 % bands, the
extremes dotted); and a scatter of each metric against each swept parameter. Axes carry the
declared units. Drawn on a matplotlib.figure.Figure: pyplot and the process's backend are never
touched."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Sequence

import numpy as np

from compiler.errors import DyadError
from compiler.sweep.writers import atomic_write

MAX_SIGNALS = 3
MAX_SCATTERS = 4
MAX_LEGEND_LINES = 12     # a grid of more values gets a colour bar instead of a legend


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
        draw = _grid_lines if result.design.method == "grid" else _fan
        for k, name in enumerate(signals):
            draw(figure.add_subplot(grid[row, k]), result, name)
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
    _signal_axes(ax, result, name)


def _grid_lines(ax, result, name: str) -> None:
    """One line per grid value, coloured along the grid and labelled with its parameter values."""
    time, values, samples = result.signal(name)
    colors = _colormap()(np.linspace(0.0, 1.0, max(len(samples), 1)))
    for row, sample, color in zip(values, samples, colors):
        label = ", ".join(f"{n} = {v:g}{_unit_suffix(result, n)}"
                          for n, v in result.parameter_values(sample).items())
        ax.plot(time, row, color=color, lw=1.1, label=label)
    if 0 < len(samples) <= MAX_LEGEND_LINES:
        ax.legend(fontsize="x-small", loc="best")
    _signal_axes(ax, result, name)


def _colormap():
    from matplotlib import colormaps
    return colormaps["viridis"]


def _signal_axes(ax, result, name: str) -> None:
    ax.set_title(name, fontsize="small")
    ax.set_xlabel("time [s]")
    ax.set_ylabel(f"{name}{_unit_suffix(result, name)}", fontsize="small")
    ax.grid(True, alpha=0.3)


def _unit_suffix(result, name: str) -> str:
    """` [unit]` for a name with a declared unit, else nothing."""
    unit = result.units.get(name)
    return f" [{unit}]" if unit else ""


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
    ax.set_xlabel(f"{parameter}{_unit_suffix(result, parameter)}")
    ax.set_ylabel(metric)
    ax.grid(True, alpha=0.3)


def save_figure(figure, path: str | os.PathLike) -> Path:
    path = Path(path)
    form = path.suffix.lstrip(".").lower() or "png"
    atomic_write(path, lambda tmp: figure.savefig(tmp, format=form, dpi=110))
    return path
