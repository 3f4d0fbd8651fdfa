"""Plots of linear models (matplotlib, Agg): Bode (magnitude and phase, or magnitude only),
Nyquist, step responses. Each writes a PNG and returns its path."""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from compiler.linear.system import LinearSystem


def frequency_grid(systems: Sequence[LinearSystem], wl: float = -1.0, wu: float = -1.0,
                   count: int = 1000) -> np.ndarray:
    """count frequencies (rad/s) from wl to wu, log-spaced; a bound <= 0 is taken two decades
    beyond the smallest or largest pole magnitude of `systems`."""
    magnitudes = [abs(p) for s in systems for p in s.poles() if abs(p) > 1e-9]
    low = wl if wl > 0 else (min(magnitudes) / 100 if magnitudes else 1e-2)
    high = wu if wu > low else (max(magnitudes) * 100 if magnitudes else max(1e3, 1e3 * low))
    return np.logspace(math.log10(low), math.log10(high), count)


def figure(rows: int = 1):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt, plt.subplots(rows, 1, figsize=(7, 2.6 * rows + 0.6), squeeze=False)


def bode_plot(curves, omega, path: str, title: str, magnitude_only: bool = False) -> str:
    plt, (fig, axes) = figure(1 if magnitude_only else 2)
    for system, label in curves:
        response = np.asarray(system(1j * omega)).reshape(-1, len(omega))
        for k, row in enumerate(response):
            name = label if response.shape[0] == 1 else f"{label} [{k + 1}]"
            axes[0][0].loglog(omega, np.abs(row), label=name or None)
            if not magnitude_only:
                axes[1][0].semilogx(omega, np.degrees(np.unwrap(np.angle(row))), label=name or None)
    axes[0][0].set_ylabel("magnitude")
    axes[0][0].set_title(title)
    if not magnitude_only:
        axes[1][0].set_ylabel("phase (deg)")
    axes[-1][0].set_xlabel("frequency (rad/s)")
    for row in axes:
        row[0].grid(True, which="both", alpha=0.3)
        if any(label for _, label in curves):
            row[0].legend(fontsize=8)
    return save(plt, fig, path)


def nyquist_plot(loop, omega, path: str) -> str:
    plt, (fig, axes) = figure(1)
    fig.set_size_inches(6, 6)
    response = np.asarray(loop(1j * omega)).reshape(-1)
    ax = axes[0][0]
    ax.plot(response.real, response.imag, label="L(iw)")
    ax.plot(response.real, -response.imag, "--", alpha=0.5, label="L(-iw)")
    ax.plot([-1], [0], "r+", markersize=12, label="-1")
    circle = np.exp(1j * np.linspace(0, 2 * np.pi, 200))
    ax.plot(circle.real, circle.imag, ":", color="gray", linewidth=0.8, label="|L| = 1")
    reach = max(2.0, min(float(np.max(np.abs(response))), 4.0))     # the part near -1 matters
    ax.set_xlim(-reach, reach)
    ax.set_ylim(-reach, reach)
    ax.set_aspect("equal")
    ax.set_xlabel("real")
    ax.set_ylabel("imaginary")
    ax.set_title("Nyquist plot of the loop transfer")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return save(plt, fig, path)


def step_plot(step, system: LinearSystem, path: str) -> str:
    plt, (fig, axes) = figure(1)
    outputs = np.asarray(step.outputs).reshape(len(system.outputs), len(system.inputs), -1)
    for i, out in enumerate(system.outputs):
        for j, inp in enumerate(system.inputs):
            axes[0][0].plot(step.time, outputs[i, j], label=f"{inp} -> {out}")
    axes[0][0].set_xlabel("time (s)")
    axes[0][0].set_title("step response of the linear model")
    axes[0][0].grid(True, alpha=0.3)
    axes[0][0].legend(fontsize=8)
    return save(plt, fig, path)


def steps_plot(systems: Mapping[str, Any], duration: float, path: str) -> str:
    import control
    plt, (fig, axes) = figure(1)
    for label, system in systems.items():
        step = control.step_response(system, T=duration if duration > 0 else None)
        axes[0][0].plot(step.time, np.asarray(step.outputs).reshape(-1, len(step.time))[0], label=label)
    axes[0][0].set_xlabel("time (s)")
    axes[0][0].set_title("closed-loop step responses")
    axes[0][0].grid(True, alpha=0.3)
    axes[0][0].legend(fontsize=8)
    return save(plt, fig, path)


def save(plt, fig, path: str) -> str:
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
