"""Plots of result signals: one subplot per unit, each titled and with its unit on the y-axis.

Signals of different units on one axis hide each other (a pressure of 1e7 Pa flattens an angle of
1 rad), so they are grouped by unit. The figure is a bare matplotlib `Figure` saved through its own
canvas: pyplot is never imported, so the user's matplotlib backend and open figures are untouched.
"""
from __future__ import annotations

import os
from typing import Mapping

import numpy as np

from .writers import atomic_write

PLOT_EXTENSIONS = (".png", ".pdf", ".svg", ".svgz", ".eps", ".ps", ".jpg", ".jpeg", ".tif", ".tiff",
                   ".webp")
NO_UNIT = "no unit"
_SUBPLOT_HEIGHT = 2.4     # inches per unit group
_MAX_LEGEND_ENTRIES = 12  # more signals than this on one axis make an unreadable legend


class PlotFormatError(ValueError):
    """A plot file name whose extension names no image format matplotlib writes."""


def plot_format(path: str | os.PathLike) -> str:
    """The image format `path` asks for (its extension without the dot); a PlotFormatError for
    any other extension."""
    extension = os.path.splitext(os.fspath(path))[1].lower()
    if extension not in PLOT_EXTENSIONS:
        shown = extension or "no extension"
        raise PlotFormatError(f"cannot write a plot to `{os.fspath(path)}` ({shown}): supported "
                              f"extensions are {', '.join(PLOT_EXTENSIONS)}")
    return extension[1:]


def group_by_unit(names, units: Mapping[str, str] | None) -> dict[str, list[str]]:
    """Signal names per unit, units in order of first appearance; signals without one share
    the group NO_UNIT."""
    groups: dict[str, list[str]] = {}
    for name in names:
        groups.setdefault((units or {}).get(name) or NO_UNIT, []).append(name)
    return groups


def plot_signals(path: str | os.PathLike | None, time, columns: Mapping[str, np.ndarray],
                 units: Mapping[str, str] | None, title: str):
    """Draw `columns` over `time`, one subplot per unit, and write the image to `path` atomically
    (format from the extension; no file when `path` is None). Returns the Figure."""
    from matplotlib.figure import Figure

    image_format = None if path is None else plot_format(path)
    groups = group_by_unit(list(columns), units)
    rows = max(len(groups), 1)
    figure = Figure(figsize=(11, 1.2 + _SUBPLOT_HEIGHT * rows), layout="constrained")
    axes = figure.subplots(rows, 1, sharex=True, squeeze=False)[:, 0]
    time = np.asarray(time, dtype=float)
    for ax, (unit, names) in zip(axes, groups.items()):
        for name in names:
            ax.plot(time, np.asarray(columns[name], dtype=float), label=name)
        ax.set_title(_group_title(unit, names), fontsize="medium", loc="left")
        ax.set_ylabel(unit if unit == NO_UNIT else f"[{unit}]")
        ax.grid(True, alpha=0.3)
        if len(names) <= _MAX_LEGEND_ENTRIES:
            # beside the axes: a legend inside hides the curves it names
            ax.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    axes[-1].set_xlabel("time [s]")
    figure.suptitle(title)
    if path is not None:
        atomic_write(path, lambda temp: figure.savefig(temp, format=image_format))
    return figure


def _group_title(unit: str, names: list[str]) -> str:
    if len(names) <= 3:
        return ", ".join(names)
    return f"{len(names)} signals in {unit}" if unit != NO_UNIT else f"{len(names)} signals without a unit"
