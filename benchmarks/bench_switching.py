"""Speed of a run that switches state sets (issue 15 item 3) -> docs/numerics.md.

    .venv/bin/python benchmarks/bench_switching.py [--repeats 5] [--doc docs/numerics.md]

The pendulum released at 2.3 rad (L = 0.8 m, tests/models/Hard/PendulumA01.dyad), 20 s, rtol =
atol = 1e-8, 2001 output points, compiled once, against the floor: one CasADi IDAS run of the
hand-reduced angle ODE at the same tolerances and grid, side by side in this process (CPU time,
medians). The profile splits our run by where its CPU time goes. The table replaces the text
between the markers in the doc.
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

from compiler import api  # noqa: E402

BEGIN, END = "<!-- switching speed: begin -->", "<!-- switching speed: end -->"
THETA0, L, G, STOP, RTOL, POINTS = 2.3, 0.8, 9.81, 20.0, 1e-8, 2001
# where the CPU time of a run goes: (label, functions whose cumulative time counts there)
PHASES = (("IDAS integration", ("Function_call",)), ("IDAS construction", ("casadi._casadi.integrator",)),
          ("state-set switches", ("switch_state_set",)), ("checks (watched functions)", ("watched_values",)),
          ("outputs and polishing", ("finish",)))


def cpu(call) -> tuple[float, object]:
    began = time.process_time()
    value = call()
    return time.process_time() - began, value


def measure(repeats: int) -> dict:
    compilation = api.compile("Hard.PendulumA01", lib_dirs=(str(ROOT / "tests" / "models"),))
    params = {"y0": -L * np.cos(THETA0), "L": L, "g": G}

    def ours():
        return api.simulate_compiled(compilation, STOP, points=POINTS, rtol=RTOL, atol=RTOL, params=params,
                                     progress=False)
    theta, omega = ca.SX.sym("theta"), ca.SX.sym("omega")
    grid = [float(t) for t in np.linspace(0.0, STOP, POINTS)[1:]]

    def floor():
        solver = ca.integrator("angle", "idas", {"x": ca.vertcat(theta, omega),
                                                  "ode": ca.vertcat(omega, -G / L * ca.sin(theta))},
                               0.0, grid, {"reltol": RTOL, "abstol": RTOL})
        solver(x0=[THETA0, 0.0])
        return solver
    ours(), floor()                                           # warm-up
    ours_times, floor_times, result, solver = [], [], None, None
    for _ in range(repeats):                                  # side by side, alternating
        seconds, result = cpu(ours)
        ours_times.append(seconds)
        seconds, solver = cpu(floor)
        floor_times.append(seconds)
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
            "steps": result.stats["steps"], "calls": result.stats["segments"],
            "switches": len(result.stats["state_switches"]), "floor_steps": int(solver.stats()["nsteps"]),
            "profile_total": total, "phases": phases}


def render(data: dict, repeats: int) -> str:
    lines = [BEGIN, "",
             f"The pendulum released at {THETA0} rad (L = {L} m), {STOP:g} s, rtol = atol = {RTOL:g}, "
             f"{POINTS} output points, CPU medians of {repeats} side by side in one process:", "",
             "| run | CPU | IDAS steps | IDAS calls | switches |", "|---|---|---|---|---|",
             f"| dyadc, switching state sets | {data['ours'] * 1e3:.0f} ms | {data['steps']} | {data['calls']} "
             f"| {data['switches']} |",
             f"| one IDAS run of the angle ODE (the floor) | {data['floor'] * 1e3:.1f} ms | "
             f"{data['floor_steps']} | 1 | 0 |",
             "", f"Ratio: **{data['ours'] / data['floor']:.0f}x** the floor (the issue asks for 5x).", "",
             "Where one run's time goes (cProfile, cumulative, of "
             f"{data['profile_total'] * 1e3:.0f} ms under the profiler):", ""]
    lines += [f"- {label}: {seconds * 1e3:.0f} ms" for label, seconds in data["phases"].items()]
    lines += ["", END]
    return "\n".join(lines)


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--doc", default=str(ROOT / "docs" / "numerics.md"))
    args = parser.parse_args(argv)
    table = render(measure(args.repeats), args.repeats)
    doc = Path(args.doc)
    text = doc.read_text(encoding="utf-8") if doc.exists() else ""
    if BEGIN in text and END in text:
        text = text[:text.index(BEGIN)] + table + text[text.index(END) + len(END):]
    else:
        text = text.rstrip("\n") + "\n\n## Speed of a switching run\n\n" + table + "\n"
    doc.write_text(text, encoding="utf-8")
    print(table)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
