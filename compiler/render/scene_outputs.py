"""`make run`: the excavator dig cycle simulated once, written as CSV, dashboard PNG and GIF."""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np

EXCAVATOR = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"
STOP_TIME = 12.0
POINTS = 1201
FRAMES = 120
FPS = 12


def write_scene_outputs(out_dir: str = "out") -> list[str]:
    """Write the three files into `out_dir`; the lines that say what was written and how long
    each step took (`make run` prints them)."""
    from compiler import api
    from compiler.render.animate import animate
    from compiler.render.scene_plot import plot_excavator

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    csv_path, png_path, gif_path = out / "excavator.csv", out / "excavator.png", out / "excavator.gif"

    started = time.perf_counter()
    compilation = api.compile(EXCAVATOR)
    compiled = time.perf_counter()
    result = api.simulate_compiled(compilation, STOP_TIME, rtol=1e-6, points=POINTS)
    simulated = time.perf_counter()
    written = result.to_csv(csv_path)             # the CSV and its sidecar (parameters, units)
    plot_excavator(result, png_path)
    plotted = time.perf_counter()
    animate(compilation, result, gif_path, fps=FPS, frames=FRAMES)
    animated = time.perf_counter()

    return [f"wrote {written[0]} ({len(result.names)} signals x {len(result.time)} points) and {written[1]}",
            f"wrote {png_path}",
            f"wrote {gif_path} ({FRAMES} frames at {FPS} fps)",
            f"compile {compiled - started:.2f} s, simulate {simulated - compiled:.2f} s "
            f"({result.stats.get('steps', '?')} steps), plot {plotted - simulated:.2f} s, "
            f"animate {animated - plotted:.2f} s",
            f"payload at t = {result.time[-1]:g} s: {result['soil.m_load'][-1]:.2f} kg; "
            f"max penetration soil.d: {np.max(result['soil.d']):.4f} m"]
