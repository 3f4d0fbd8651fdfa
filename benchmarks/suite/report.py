"""docs/benchmarks.md from the measured data."""
from __future__ import annotations

import math

from suite.compile_time import STAGES
from suite.problems import EXCAVATOR_GROUPS
from suite.workprecision import speedups


def _s(seconds: float) -> str:
    if seconds is None or (isinstance(seconds, float) and math.isnan(seconds)):
        return "-"
    return f"{seconds * 1e3:.1f} ms" if seconds < 1 else f"{seconds:.2f} s"


def _headline(runs, compile_data, floor=None) -> list[str]:
    lines = ["## Headline", ""]
    for run in runs:
        rows = speedups(run)
        for contender in ("dyadc (VM)", "dyadc (C)"):
            mine = [r for r in rows if r["contender"] == contender]
            if mine:
                lo = min(mine, key=lambda r: r["speedup"])
                hi = max(mine, key=lambda r: r["speedup"])
                lines.append(f"- **{run.problem.key}**, {contender} vs the fastest scipy method at matched error: "
                             f"{lo['speedup']:.2g}x (at error {lo['error']:.0e}) to {hi['speedup']:.2g}x "
                             f"(at error {hi['error']:.0e}).")
            elif any(c.contender == contender for c in run.curves):
                lines.append(f"- **{run.problem.key}**, {contender}: no error level reached by both it and a "
                             "scipy method (no matched-error comparison).")
    for row in (floor or {}).get("matched", {}).get("dyadc", []):
        s = floor["matched"]["scipy"]
        lines.append(f"- **Excavator at matched tip error**: {row['contender']} at rtol {row['rtol']:.0e} "
                     f"(tip error {row['tip']:.1e} m) is {row['speedup']:.0f}x faster than the hand-written "
                     f"scipy {s['method']} model at rtol {s['rtol']:.0e} (tip error {s['tip']:.1e} m).")
    exc = compile_data.get("excavator", {}).get("median", {})
    if exc:
        compile_s = sum(exc[s] for s in ("parse", "flatten", "structure", "lower"))
        lines.append(f"- **Excavator compile time** (cold process, median): {compile_s:.2f} s from source to "
                     f"CasADi functions (+ {exc['import']:.2f} s imports, first 12 s simulation "
                     f"{exc['simulate']:.2f} s, uncached C build {exc.get('c_build', float('nan')):.2f} s).")
    chain = compile_data.get("chain", {})
    if chain.get("fit"):
        lines.append(f"- **Compile-time growth** for an N-link chain: total ~ N^{chain['fit']['total']:.2f} "
                     f"(log-log fit over N >= {chain['fit_from']}); the largest measured chain "
                     f"(N = {chain['rows'][-1]['n']}) took {chain['rows'][-1]['total']:.1f} s"
                     + (f"; between N = {chain['rows'][-2]['n']} and {chain['rows'][-1]['n']} the total grows as "
                        f"N^{math.log(chain['rows'][-1]['total'] / chain['rows'][-2]['total']) / math.log(chain['rows'][-1]['n'] / chain['rows'][-2]['n']):.2f}"
                        if len(chain["rows"]) >= 2 else "") + ".")
    return lines + [""]


def _point_table(run) -> list[str]:
    excavator = run.problem.key == "excavator"
    head = "| contender | rtol | atol | runs | median time | error |"
    sep = "|---|---|---|---|---|---|"
    if excavator:
        head += "".join(f" {g} max | {g} final |" for g in EXCAVATOR_GROUPS)
        sep += "---|---|" * len(EXCAVATOR_GROUPS)
    lines = [head + " status |", sep + "---|"]
    for curve in run.curves:
        for p in curve.points:
            atol = p.tolerance * run.problem.atol_ratio
            cells = [curve.contender, f"{p.tolerance:.0e}", f"{atol:.0e}", str(p.runs) if p.runs else "-",
                     _s(p.time) if p.runs else "-", f"{p.errors['error']:.2e}" if p.errors else "-"]
            if excavator:
                for g in EXCAVATOR_GROUPS:
                    cells += [f"{p.errors[f'{g} max']:.1e}" if p.errors else "-",
                              f"{p.errors[f'{g} final']:.1e}" if p.errors else "-"]
            status = p.status if not p.note else f"{p.status}: {p.note}"
            lines.append("| " + " | ".join(cells) + f" | {status.replace('|', '/')} |")
    return lines


def _speedup_table(run) -> list[str]:
    rows = speedups(run)
    if not rows:
        return ["No error level is reached by both a dyadc curve and a scipy curve."]
    lines = ["| error | contender | its time | fastest scipy | scipy time | speed-up |", "|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['error']:.0e} | {r['contender']} | {_s(r['time'])} | {r['best_scipy']} | "
                     f"{_s(r['scipy_time'])} | {r['speedup']:.2f}x |")
    return lines


def _problem_section(run, png: str) -> list[str]:
    p = run.problem
    lines = [f"### {p.title}", "", f"Error measure: {p.error_label}.", ""]
    lines += [f"- {note}" for note in p.notes]
    if p.key == "excavator":
        info = p.reference_info
        lines.append(f"- Reference: the independent hand-derived model (tests/reference/excavator_minimal.py, "
                     f"19 states in minimal coordinates) at rtol = atol = 1e-12 with LSODA, restarted at the "
                     f"reference's waypoints ({info.get('seconds', float('nan')):.1f} s). It was chosen over "
                     "dyadc at 1e-12 because it is independent of the compiler under test and because it "
                     "is cheap at that tolerance.")
        check = info.get("radau_vs_lsoda")
        if check:
            lines.append("- Reference self-check, Radau vs LSODA both at 1e-12 (same error measure): "
                         + ", ".join(f"{g} {check[f'{g} max']:.1e}" for g in EXCAVATOR_GROUPS)
                         + ", i.e. the reference is good to about that level; errors below it are not resolved.")
        for curve in run.curves:
            if curve.contender.startswith("dyadc") and curve.ok():
                tight = min(curve.ok(), key=lambda pt: pt.tolerance)
                lines.append(f"- Agreement of {curve.contender} at its tightest tolerance (rtol {tight.tolerance:.0e}) "
                             "with the reference, max over the grid / at t = 12 s: "
                             + ", ".join(f"{g} {tight.errors[f'{g} max']:.1e} / {tight.errors[f'{g} final']:.1e}"
                                         for g in EXCAVATOR_GROUPS) + ".")
        lines.append("- Groups: " + "; ".join(f"{g}: {', '.join(names)}" for g, names in EXCAVATOR_GROUPS.items())
                     + ". Each group's error is divided by the largest |value| of the group's reference signals.")
        lines.append("- dyadc: the scene's Dyad model with IDAS (absolute tolerances scaled per unknown by the "
                     "nominals the compiler derives); scipy: the hand-derived model, atol scaled per state "
                     "(benchmarks/contenders/scipy_excavator.py), one solve_ivp call over [0, 12] s.")
    for name, why in run.unavailable.items():
        lines.append(f"- **{name} unavailable**: {why}")
    lines += ["", f"![work-precision {p.key}]({png})", "", "Speed-up at matched error (piecewise-linear "
              "interpolation of log time against log error; only where both curves reach the error):", ""]
    lines += _speedup_table(run)
    lines += ["", "<details><summary>All points</summary>", ""] + _point_table(run) + ["", "</details>", ""]
    return lines


def _compile_section(compile_data: dict, png: str | None) -> list[str]:
    lines = ["## Compile time", ""]
    exc = compile_data.get("excavator")
    if exc:
        m, sizes = exc["median"], exc["sizes"]
        lines += [f"Excavator (`{'MultibodyComponents.PlanarMechanics.examples.excavator.Excavator'}`, "
                  f"{sizes.get('equations', '?')} flat equations, {sizes.get('states', '?')} states, "
                  f"{sizes.get('algebraics', '?')} IDAS algebraics), each run in a fresh Python process, "
                  f"median of {exc['runs']}:", "",
                  "| import | parse | flatten | structure | lower | first simulate (12 s, rtol 1e-6) | C build (uncached) | whole process |",
                  "|---|---|---|---|---|---|---|---|",
                  "| " + " | ".join(_s(m.get(k)) for k in ["import", *STAGES, "c_build", "process"]) + " |", "",
                  "parse includes loading (or building) the LALR parser in the cold process; flatten excludes parsing; "
                  "import is the compiler's own imports (sympy, casadi, lark, numpy).", ""]
        for problem in exc["problems"]:
            lines.append(f"- a run failed: `{problem}`")
    chain = compile_data.get("chain")
    if chain:
        lines += ["Chain of N planar links (World + N x (Revolute + BodyShape), generated in a temporary "
                  "directory; benchmarks/suite/chain_model.py), one warm process (the parser is built "
                  "and the library parsed during a warm-up on N = 1), first simulation 0.5 s at rtol 1e-6:", ""]
        lines += ["| N | equations | states | " + " | ".join(STAGES) + " | total |",
                  "|---|---|---|" + "---|" * (len(STAGES) + 1)]
        for r in chain["rows"]:
            lines.append(f"| {r['n']} | {r['equations']} | {r['states']} | "
                         + " | ".join(_s(r[s]) for s in STAGES) + f" | {_s(r['total'])} |")
        for s in chain["skipped"]:
            lines.append(f"| {s['n']} | - | - | " + " | ".join("-" for _ in STAGES) + f" | not measured: {s['why']} |")
        if chain["fit"]:
            lines += ["", f"Growth exponents (least-squares slope of log time against log N, N >= {chain['fit_from']}): "
                      + ", ".join(f"{k} {v:.2f}" for k, v in chain["fit"].items()) + "."]
            if len(chain["rows"]) >= 2:
                a, b = chain["rows"][-2], chain["rows"][-1]
                local = {s: math.log(b[s] / a[s]) / math.log(b["n"] / a["n"])
                         for s in STAGES + ["total"] if a[s] > 0 and b[s] > 0}
                lines.append(f"Local exponents between the two largest chains (N = {a['n']} -> {b['n']}), a better "
                             "guide to larger models: " + ", ".join(f"{k} {v:.2f}" for k, v in local.items()) + ".")
        if png:
            lines += ["", f"![compile time vs N]({png})"]
    return lines + [""]


def _floor_section(floor: dict) -> list[str]:
    """bench_floor.py's table and the matched-tip-error comparison (issue 15 items 1 and 2)."""
    if not floor:
        return []
    import bench_floor
    from suite.matched import report_lines
    lines = ["## Run time against the floor", ""]
    if floor.get("rows"):
        lines += ["Excavator, 12 s at rtol = atol = 1e-6: `runtime.simulate` (initialization, IDAS with the "
                  "in-run checks, polishing, outputs) against a bare CasADi IDAS run of the same compiled DAE "
                  "from the same consistent point, one `casadi.integrator` per segment between the model's "
                  "time events, x and z on the grid (benchmarks/bench_floor.py). CPU milliseconds of this "
                  "process, medians of interleaved runs; target: ratio <= 1.5.", ""]
        lines += bench_floor.table(floor["rows"]) + [""]
        lines += ["IDAS objects are kept per model (compiler/runtime/integrator.py), so a repeated run "
                  "builds none: the floor's \"building\" is what the first run of a grid costs on top, and the "
                  "last ratios compare with the floor's IDAS calls alone (a bare run that kept its integrators). "
                  "The state difference (largest over the states of max |ours - floor| / max |floor|) is "
                  "IDAS's own: the floor leaves the first step of a segment to IDAS, whose choice depends "
                  "on the first output time; the driver sets it (hence the different step counts).", ""]
    if floor.get("matched"):
        lines += report_lines(floor["matched"])
    return lines


def render(machine: dict, runs, compile_data: dict, pngs: dict, settings: dict, elapsed: float,
           floor: dict | None = None, targets: list[str] | None = None) -> str:
    lines = ["# Benchmarks", "",
             "*Generated by `.venv/bin/python benchmarks/run_all.py"
             + (" --quick" if settings["quick"] else "") + "`" + ("" if settings["quick"] else " (`make bench`)")
             + f" in {elapsed / 60:.1f} min. Do not edit by hand: "
             "regenerate with `make bench` (full, ~15 min) or `.venv/bin/python benchmarks/run_all.py --quick`.*", "",
             "| machine | |", "|---|---|"] + [f"| {k} | {v} |" for k, v in machine.items()] + [""]
    lines += _headline(runs, compile_data, floor)
    lines += targets or []
    lines += ["## Method", "",
              f"- Tolerance sweep rtol = {', '.join(f'{t:.0e}' for t in settings['tolerances'])}, atol = rtol "
              "(times a per-problem ratio, stated below), the same for every contender. All measurements in one "
              "process and one run; one untimed warm-up solve per contender and problem, then each point is the "
              f"median of up to {settings['repeats']} solves: fewer when one solve is slow (the repeats of a point "
              f"are kept within ~{settings['repeat_window']:.0f} s; the `runs` column says how many).",
              f"- Each contender has a time budget per problem ({settings['budget']:.0f} s; excavator "
              f"{settings['excavator_budget']:.0f} s). Tighter tolerances whose predicted run time (extrapolated "
              "from the last two points) exceeds the remaining budget are marked *skipped*; a solver error is "
              "marked *failed* with its message.",
              "- Contenders: **dyadc (VM)** = `compiler.api.compile` + `api.simulate_compiled` (IDAS through "
              "CasADi's SX virtual machine); **dyadc (C)** = the same model with its DAE, its Jacobian, its outputs "
              "and the polishing Newton step compiled to a shared library by `compiler.cache.c_code.compile_c`; **scipy Radau / BDF / LSODA** = "
              "`benchmarks/contenders/scipy_*.py` (solve_ivp on hand-written independent models, with Jacobians). "
              "Times exclude compilation (see Compile time) and include initialization and output evaluation.",
              "- The machine is shared with other work, so times carry noise of a few tens of percent; the "
              "load average above is a hint of how busy it was.", ""]
    lines += _floor_section(floor or {})
    lines += ["## Work-precision", ""]
    for run in runs:
        lines += _problem_section(run, pngs[run.problem.key])
    lines += _compile_section(compile_data, pngs.get("compile"))
    return "\n".join(lines).rstrip() + "\n"
