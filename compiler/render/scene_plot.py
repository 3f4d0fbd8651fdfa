"""The excavator dashboard: six panels over the dig cycle (signal names of scene section 6)."""
from __future__ import annotations

import numpy as np

from compiler.errors import DyadError
from compiler.runtime.writers import atomic_write

AXES = ("boom", "stick", "bucket")
AXIS_COLORS = {"boom": "#1f77b4", "stick": "#ff7f0e", "bucket": "#2ca02c"}
SOIL_COLOR = (0.47, 0.35, 0.2)


def required_signals() -> list[str]:
    names = [f"{axis}_joint.phi" for axis in AXES]
    names += ["bucket.frame_b.x", "bucket.frame_b.y"]
    for axis in AXES:
        names += [f"{axis}_cyl.cylinder.s", f"reference.s_{axis}",
                  f"{axis}_cyl.cylinder.p_a", f"{axis}_cyl.cylinder.p_b"]
    names += ["soil.F_x", "soil.F_y", "soil.F_cut", "soil.m_load"]
    return names


def plot_excavator(result, path) -> None:
    """Write the dashboard PNG of an excavator result to `path` (atomically)."""
    missing = [name for name in required_signals() if name not in result]
    if missing:
        raise DyadError(f"cannot plot the excavator: the result lacks {', '.join(missing[:4])}"
                        + (f" and {len(missing) - 4} more" if len(missing) > 4 else ""))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, panels = plt.subplots(3, 2, figsize=(13, 11))
    try:
        _joint_angles(panels[0, 0], result)
        _tip_path(panels[0, 1], result)
        _cylinder_positions(panels[1, 0], result)
        _pressures(panels[1, 1], result)
        _soil_forces(panels[2, 0], result)
        _payload(panels[2, 1], result)
        fig.suptitle(f"{result.model_name or 'Excavator'}: dig cycle", fontsize=14)
        fig.tight_layout()
        atomic_write(path, lambda temp_path: fig.savefig(temp_path, dpi=100))
    finally:
        plt.close(fig)


def _time_panel(ax, title: str, ylabel: str) -> None:
    ax.set_title(title)
    ax.set_xlabel("time [s]")
    ax.set_ylabel(ylabel)
    ax.grid(True, alpha=0.3)


def _joint_angles(ax, result) -> None:
    for axis in AXES:
        ax.plot(result.time, np.degrees(result[f"{axis}_joint.phi"]), color=AXIS_COLORS[axis],
                label=f"{axis}_joint.phi")
    _time_panel(ax, "Joint angles (relative)", "angle [deg]")
    ax.legend(fontsize="small")


def _tip_path(ax, result) -> None:
    x, y = result["bucket.frame_b.x"], result["bucket.frame_b.y"]
    depth = max(0.3, -1.5 * float(np.min(y)))
    top = max(float(np.max(y)), 0.0) + 0.3
    # The soil band spans any x range, so the equal aspect may widen the x limits freely.
    ax.axhspan(-10 * depth, 0.0, color=SOIL_COLOR, alpha=0.45, lw=0, label="soil (y < 0)")
    ax.axhline(0.0, color=SOIL_COLOR, lw=1.5)
    points = ax.scatter(x, y, c=result.time, cmap="viridis", s=4, zorder=3)
    ax.plot(x, y, color="black", lw=0.6, alpha=0.5, zorder=2)
    ax.plot([x[0]], [y[0]], "o", color="black", label="start", zorder=4)
    ax.plot([x[-1]], [y[-1]], "s", color="black", label="end", zorder=4)
    ax.figure.colorbar(points, ax=ax, label="time [s]")
    ax.set_ylim(-depth, top)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title("Bucket tip path (bucket.frame_b)")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize="small", loc="upper right")


def _cylinder_positions(ax, result) -> None:
    for axis in AXES:
        color = AXIS_COLORS[axis]
        ax.plot(result.time, result[f"{axis}_cyl.cylinder.s"], color=color, label=f"{axis}_cyl.cylinder.s")
        ax.plot(result.time, result[f"reference.s_{axis}"], color=color, ls="--", lw=1,
                label=f"reference.s_{axis}")
    _time_panel(ax, "Piston positions vs references", "s [m]")
    ax.legend(fontsize="x-small", ncol=2)


def _pressures(ax, result) -> None:
    for axis in AXES:
        color = AXIS_COLORS[axis]
        ax.plot(result.time, result[f"{axis}_cyl.cylinder.p_a"] / 1e6, color=color, label=f"{axis} p_a")
        ax.plot(result.time, result[f"{axis}_cyl.cylinder.p_b"] / 1e6, color=color, ls=":",
                label=f"{axis} p_b")
    _time_panel(ax, "Chamber pressures", "pressure [MPa]")
    ax.legend(fontsize="x-small", ncol=3)


def _shade_in_soil(ax, result) -> None:
    in_soil = result["bucket.frame_b.y"] < 0
    if np.any(in_soil):
        ax.fill_between(result.time, 0, 1, where=in_soil, transform=ax.get_xaxis_transform(),
                        color=SOIL_COLOR, alpha=0.15, lw=0, label="tip in soil")


def _soil_forces(ax, result) -> None:
    _shade_in_soil(ax, result)
    for name, color in (("soil.F_x", "#d62728"), ("soil.F_y", "#9467bd"), ("soil.F_cut", "#8c564b")):
        ax.plot(result.time, result[name] / 1e3, color=color, label=name)
    _time_panel(ax, "Soil forces on the tool", "force [kN]")
    ax.legend(fontsize="small")


def _payload(ax, result) -> None:
    _shade_in_soil(ax, result)
    ax.plot(result.time, result["soil.m_load"], color=SOIL_COLOR, lw=2, label="soil.m_load")
    _time_panel(ax, "Payload", "mass [kg]")
    ax.legend(fontsize="small")
