"""Accuracy of dynamic state selection and of the error control (issue 16) -> docs/numerics.md.

    .venv/bin/python benchmarks/bench_accuracy.py [--quick] [--doc docs/numerics.md]

Significant digits per variable, -log10(max over the grid of |error| / max |reference|), against
closed forms and the Test Set: the A01 pendulum (tests/models/Hard/PendulumA01.dyad, released
with the rod horizontal) and the pendulum released at 2.3 rad (L = 0.8 m), each beside one IDAS
run of the hand-reduced angle ODE at the same tolerances; Andrews' squeezer at t = 0.03 s with the
runtime's error control (dummy states in IDAS's error test) and with the states only. The table
replaces the text between the markers in the doc.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import casadi as ca
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from compiler import api  # noqa: E402
from compiler.runtime import idas  # noqa: E402
from suite.doc_blocks import write_block  # noqa: E402
from tests.reference import andrews, pendulum  # noqa: E402

MODELS = str(ROOT / "tests" / "models")
BEGIN, END = "<!-- accuracy table: begin -->", "<!-- accuracy table: end -->"
PENDULUM_SIGNALS = (("x", "x"), ("y", "y"), ("vx", "vx"), ("vy", "vy"), ("lambda", "tension"))


def digits(error: float, scale: float) -> float:
    return float(-np.log10(max(error, 1e-300) / scale))


def angle_ode_digits(times, rtol, theta0, L, g) -> tuple[float, int]:
    theta, omega = ca.SX.sym("theta"), ca.SX.sym("omega")
    solver = ca.integrator("angle", "idas", {"x": ca.vertcat(theta, omega),
                                              "ode": ca.vertcat(omega, -g / L * ca.sin(theta))},
                           0.0, [float(t) for t in times[1:]], {"reltol": rtol, "abstol": rtol})
    angles = np.concatenate([[theta0], np.asarray(solver(x0=[theta0, 0.0])["xf"])[0]])
    ref = pendulum.solution(times, theta0=theta0, L=L, g=g)
    return digits(np.max(np.abs(L * np.sin(angles) - ref["x"])), np.max(np.abs(ref["x"]))), \
        int(solver.stats()["nsteps"])


def pendulum_rows(stop: float, theta0: float, L: float, tolerances) -> list[str]:
    compilation = api.compile("Hard.PendulumA01", lib_dirs=(MODELS,))
    g = 9.81
    rows = []
    for rtol in tolerances:
        began = time.perf_counter()
        res = api.simulate_compiled(compilation, stop, points=1001, rtol=rtol, atol=rtol,
                                    params={"y0": -L * np.cos(theta0), "L": L, "g": g})
        seconds = time.perf_counter() - began
        ref = pendulum.solution(res.time, theta0=theta0, L=L, g=g)
        ref["tension"] = ref["tension"] / L
        found = [digits(np.max(np.abs(res[n] - ref[k])), np.max(np.abs(ref[k]))) for n, k in PENDULUM_SIGNALS]
        angle, angle_steps = angle_ode_digits(res.time, rtol, theta0, L, g)
        rows.append(f"| {rtol:.0e} | " + " | ".join(f"{d:.1f}" for d in found)
                    + f" | {angle:.1f} | {len(res.stats['state_switches'])} | {res.stats['steps']} "
                      f"| {angle_steps} | {seconds:.2f} |")
    return rows


def andrews_rows(tolerances) -> list[str]:
    compilation = api.compile("Hard.AndrewsSqueezerAccelerations", lib_dirs=(MODELS,))
    acc_ref, mult_ref = andrews.accelerations_and_multipliers(andrews.REFERENCE_ANGLES, andrews.REFERENCE_RATES)
    rates = ("bep", "thp", "gap", "php", "dep", "omp", "epp")
    accelerations = ("a_beta", "a_Theta", "a_gamma", "a_Phi", "a_delta", "a_Omega", "a_epsilon")
    rows = []
    for control in ("dummy states", "states only"):
        for rtol in tolerances:
            options = {"suppress_algebraic": True} if control == "states only" else {}
            original = idas.error_controlled
            if control == "states only":
                idas.error_controlled = lambda model: set()
            try:
                res = api.simulate_compiled(compilation, andrews.T_END, points=31, rtol=rtol, atol=rtol,
                                            integrator_options=options)
            except Exception as failure:            # noqa: BLE001 - reported in the table
                rows.append(f"| {control} | {rtol:.0e} | failed: {str(failure).splitlines()[0][-90:]} | | | | |")
                continue
            finally:
                idas.error_controlled = original

            def worst(names, reference):
                values = np.array([res[n][-1] for n in names])
                return float(np.min(-np.log10(np.abs(values - reference) / np.abs(reference))))
            rows.append(f"| {control} | {rtol:.0e} | {worst(andrews.ANGLE_NAMES, andrews.REFERENCE_ANGLES):.1f} "
                        f"| {worst(rates, andrews.REFERENCE_RATES):.1f} | {worst(accelerations, acc_ref):.1f} "
                        f"| {worst([f'lambda[{i}]' for i in range(1, 7)], mult_ref):.1f} | {res.stats['steps']} |")
    return rows


def render(quick: bool) -> str:
    tolerances = (1e-6, 1e-8, 1e-10) if quick else (1e-6, 1e-8, 1e-10, 1e-12)
    head = ("| rtol = atol | x | y | vx | vy | lambda | angle ODE, x | switches | IDAS steps "
            "| angle ODE steps | seconds |\n|---|---|---|---|---|---|---|---|---|---|---|")
    lines = [BEGIN, "", "A01 pendulum, released with the rod horizontal, 20 s, 1001 output points "
             "(significant digits against the closed form):", "", head]
    lines += pendulum_rows(20.0, np.pi / 2, 1.0, tolerances)
    if not quick:
        lines += ["", "A01 pendulum over 100 s (42 periods):", "", head]
        lines += pendulum_rows(100.0, np.pi / 2, 1.0, (1e-10, 1e-12))
    lines += ["", "Released at 2.3 rad, L = 0.8 m, 20 s:", "", head]
    lines += pendulum_rows(20.0, 2.3, 0.8, tolerances)
    lines += ["", "Andrews' squeezer at t = 0.03 s, the smallest number of significant digits per group "
              "against the Test Set (accelerations and multipliers: the exact equations at the Test "
              "Set's final state):", "",
              "| error control | rtol = atol | angles | rates | accelerations | multipliers | IDAS steps |",
              "|---|---|---|---|---|---|---|"]
    lines += andrews_rows((1e-6, 1e-8, 1e-10, 1e-11, 1e-12) if not quick else (1e-8, 1e-10))
    lines += ["", END]
    return "\n".join(lines)


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--doc", default=str(ROOT / "docs" / "numerics.md"))
    args = parser.parse_args(argv)
    table = render(args.quick)
    write_block(Path(args.doc), table, BEGIN, END)
    print(table)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
