"""Work-precision and compile-time plots (PNG, log-log)."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from suite.problems import EXCAVATOR_GROUPS  # noqa: E402

STYLES = {"dyadc (VM)": ("tab:blue", "o", "-"), "dyadc (C)": ("tab:cyan", "s", "-"),
          "scipy Radau": ("tab:red", "^", "--"), "scipy BDF": ("tab:orange", "v", "--"),
          "scipy LSODA": ("tab:green", "D", "--")}


def _draw(ax, curves, error_key: str) -> None:
    for curve in curves:
        pts = [p for p in curve.ok() if p.errors.get(error_key, 0) > 0]
        if not pts:
            continue
        color, marker, line = STYLES.get(curve.contender, ("gray", "x", ":"))
        ax.loglog([p.errors[error_key] for p in pts], [p.time for p in pts], color=color, marker=marker,
                  linestyle=line, label=curve.contender)
        for p in pts:
            ax.annotate(f"{p.tolerance:.0e}", (p.errors[error_key], p.time), fontsize=6, color=color,
                        xytext=(3, 3), textcoords="offset points")
    ax.grid(True, which="both", alpha=0.3)
    ax.set_ylabel("wall time per solve [s] (median)")


def work_precision_png(run, path: Path) -> None:
    problem = run.problem
    if problem.key == "excavator":
        fig, axes = plt.subplots(2, 2, figsize=(11, 8.5))
        for ax, group in zip(axes.ravel(), EXCAVATOR_GROUPS):
            _draw(ax, run.curves, f"{group} max")
            ax.set_title(f"{group}: max error over the grid (relative to the group's scale)", fontsize=9)
            ax.set_xlabel("error")
        axes[0, 0].legend(fontsize=8)
    else:
        fig, ax = plt.subplots(figsize=(7.5, 5.5))
        _draw(ax, run.curves, "error")
        ax.set_xlabel(problem.error_label)
        ax.legend(fontsize=8)
    fig.suptitle(f"Work-precision: {problem.title}\n(labels: rtol)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def compile_scaling_png(rows: list[dict], stages: list[str], fit: dict, path: Path) -> None:
    fig, ax = plt.subplots(figsize=(7.5, 5.5))
    n = np.array([r["n"] for r in rows], dtype=float)
    for stage in stages + ["total"]:
        values = np.array([r[stage] for r in rows], dtype=float)
        ax.loglog(n, values, marker="o", label=f"{stage}" + (f" (~N^{fit[stage]:.2f})" if stage in fit else ""),
                  linewidth=2.5 if stage == "total" else 1.2)
    ax.set_xlabel("number of links N")
    ax.set_ylabel("time [s]")
    ax.set_title("Compile time of an N-link planar chain (World + N x (Revolute + BodyShape))", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
