"""Speed of a run that switches state sets (issue 15 item 3) -> docs/numerics.md.

    .venv/bin/python benchmarks/bench_switching.py [--repeats 5] [--doc docs/numerics.md]

The pendulum released at 2.3 rad (L = 0.8 m, tests/models/Hard/PendulumA01.dyad), 20 s, rtol =
atol = 1e-8, 2001 output points, compiled once, against the floor: one CasADi IDAS run of the
hand-reduced angle ODE at the same tolerances and grid, side by side in this process (CPU time,
medians). Our run is more accurate than the floor at the same rtol (it integrates tighter after its
first switch), so the floor is also timed at matched error: the loosest rtol whose bob-position
error against the closed form (tests/reference/pendulum.py) is no larger than ours. The profile
splits our run by where its CPU time goes. The table replaces the text between the markers in
the doc.
"""
from __future__ import annotations

import argparse
import cProfile
import pstats
import sys
import time
from pathlib import Path

import casadi as ca
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from compiler import api  # noqa: E402
from compiler.runtime.integrator import COUNTERS  # noqa: E402
from suite.doc_blocks import write_block  # noqa: E402
from tests.reference import pendulum  # noqa: E402

BEGIN, END = "<!-- switching speed: begin -->", "<!-- switching speed: end -->"
THETA0, L, G, STOP, RTOL, POINTS = 2.3, 0.8, 9.81, 20.0, 1e-8, 2001
# rtols tried for the floor at matched error, loosest first
MATCHING_RTOLS = (1e-8, 5e-9, 2e-9, 1e-9, 5e-10, 2e-10, 1e-10, 5e-11, 2e-11, 1e-11)
# where the CPU time of a run goes: (label, functions whose cumulative time counts there)
PHASES = (("IDAS integration", ("Function_call",)), ("IDAS construction", ("casadi._casadi.integrator",)),
          ("state-set switches", ("switch_state_set",)),
          ("the restart point at a switch (Levenberg-Marquardt, part of the switches)", ("restart_point",)),
          ("the algebraic equations solved in C (restart points, crossings; native)", ("algebraic_solution",)),
          ("the next state set's choice (part of the switches)", ("variants.py:switch",)),
          ("every output at a crossing", ("crossing_values",)), ("checks (watched functions)", ("watched_values",)),
          ("outputs and polishing", ("finish",)),
          ("native IDAS: the driver's calls (integration)", ("library.py:advance",)),
          ("native IDAS: restarts", ("library.py:restart",)))


def cpu(call) -> tuple[float, object]:
    began = time.process_time()
    value = call()
    return time.process_time() - began, value


def measure(repeats: int, integrator=None) -> dict:
    """`integrator`: None for the default path (the native IDAS driver where it can run), "casadi"
    for CasADi's IDAS, or compiler.runtime.native.make_integrator."""
    compilation = api.compile("Hard.PendulumA01", lib_dirs=(str(ROOT / "tests" / "models"),))
    params = {"y0": -L * np.cos(THETA0), "L": L, "g": G}

    def ours():
        return api.simulate_compiled(compilation, STOP, points=POINTS, rtol=RTOL, atol=RTOL, params=params,
                                     progress=False, integrator=integrator)
    theta, omega = ca.SX.sym("theta"), ca.SX.sym("omega")
    times = np.linspace(0.0, STOP, POINTS)
    grid = [float(t) for t in times[1:]]
    exact = pendulum.solution(times, L=L, theta0=THETA0, g=G)

    def floor(rtol=RTOL):
        solver = ca.integrator("angle", "idas", {"x": ca.vertcat(theta, omega),
                                                  "ode": ca.vertcat(omega, -G / L * ca.sin(theta))},
                               0.0, grid, {"reltol": rtol, "abstol": rtol})
        solver.angles = np.concatenate([[THETA0], np.asarray(solver(x0=[THETA0, 0.0])["xf"])[0]])
        return solver

    def error(x, y) -> float:
        return float(max(np.max(np.abs(x - exact["x"])), np.max(np.abs(y - exact["y"])))) / L
    ours(), floor()                                           # warm-up
    ours_times, floor_times, result, solver = [], [], None, None
    for _ in range(repeats):                                  # side by side, alternating
        seconds, result = cpu(ours)
        ours_times.append(seconds)
        seconds, solver = cpu(floor)
        floor_times.append(seconds)
    ours_error = error(result["x"], result["y"])
    floor_error = error(L * np.sin(solver.angles), -L * np.cos(solver.angles))
    matched = None
    for rtol in MATCHING_RTOLS:
        candidate = floor(rtol)
        reached = error(L * np.sin(candidate.angles), -L * np.cos(candidate.angles))
        if reached <= ours_error:
            matched_times = []
            for _ in range(repeats):                          # side by side with ours again
                matched_times.append(cpu(lambda: floor(rtol))[0])
                ours_times.append(cpu(ours)[0])
            matched = {"rtol": rtol, "error": reached, "time": float(np.median(matched_times)),
                       "steps": int(candidate.stats()["nsteps"])}
            break
    profile = cProfile.Profile()
    profile.runcall(ours)
    stats = pstats.Stats(profile).stats
    total = sum(row[2] for row in stats.values())            # own time of every function
    phases = {}
    for label, names in PHASES:
        phases[label] = max((row[3] for key, row in stats.items()
                             if any(name in f"{key[0]}:{key[2]}" or name == key[2] for name in names)),
                            default=0.0)
    return {"ours": float(np.median(ours_times)), "floor": float(np.median(floor_times)),
            "integrator": result.stats.get("integrator"), "ours_stats": idas_counters(result.stats),
            "steps": result.stats["steps"], "calls": result.stats["segments"],
            "switches": len(result.stats["state_switches"]), "floor_steps": int(solver.stats()["nsteps"]),
            "ours_error": ours_error, "floor_error": floor_error, "matched": matched,
            "rtol_after_switch": result.stats.get("rtol_after_first_switch"),
            "profile_total": total, "phases": phases}


def idas_counters(stats: dict) -> dict:
    """IDAS's counters of a run (Result.stats), by their names in the runtime's statistics."""
    return {key: stats[key] for key in (*COUNTERS.values(), "segments") if key in stats}


def render(data: dict, repeats: int) -> str:
    lines = [BEGIN, "",
             f"The pendulum released at {THETA0} rad (L = {L} m), {STOP:g} s, rtol = atol = {RTOL:g}, "
             f"{POINTS} output points, CPU medians of {repeats} side by side in one process:", "",
             "| run | CPU | IDAS steps | IDAS calls | switches | bob position error / L |",
             "|---|---|---|---|---|---|",
             f"| dyadc, switching state sets (rtol {data['rtol_after_switch']:g} after the first switch) "
             f"| {data['ours'] * 1e3:.0f} ms | {data['steps']} | {data['calls']} | {data['switches']} "
             f"| {data['ours_error']:.2e} |",
             f"| one IDAS run of the angle ODE at the same rtol (the floor) | {data['floor'] * 1e3:.1f} ms | "
             f"{data['floor_steps']} | 1 | 0 | {data['floor_error']:.2e} |"]
    matched = data["matched"]
    if matched:
        lines.append(f"| the angle ODE at matched error (rtol {matched['rtol']:g}) | {matched['time'] * 1e3:.1f} ms "
                     f"| {matched['steps']} | 1 | 0 | {matched['error']:.2e} |")
    lines += ["", f"Ratio: **{data['ours'] / data['floor']:.0f}x** the floor at the same rtol (the issue asks "
                  f"for 5x)" + (f", **{data['ours'] / matched['time']:.0f}x** at matched error." if matched
                               else "; no tried rtol of the angle ODE matched our error."), "",
             "Where one run's time goes (cProfile, cumulative, of "
             f"{data['profile_total'] * 1e3:.0f} ms under the profiler):", ""]
    lines += [f"- {label}: {seconds * 1e3:.0f} ms" for label, seconds in data["phases"].items()
              if seconds > 0 or not label.startswith("native")]      # the native phases where it ran
    lines += ["", END]
    return "\n".join(lines)


def write_doc(table: str, doc: Path) -> None:
    """The table replaces the text between the markers (or ends the doc in a section of its own)."""
    write_block(doc, table, BEGIN, END, heading="Speed of a switching run")


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--doc", default=str(ROOT / "docs" / "numerics.md"))
    args = parser.parse_args(argv)
    table = render(measure(args.repeats), args.repeats)
    write_doc(table, Path(args.doc))
    print(table)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
