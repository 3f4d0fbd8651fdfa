"""The targets of issue 15 against what this run measured: the section of docs/benchmarks.md that
says, target by target, met or not, by how much, and (where not) what the profile of the run
shows the time goes to.

Each measurement comes from the benchmark that owns it, run in the same `make bench`:
bench_floor.py (excavator against a bare IDAS run), suite/matched.py (matched tip error),
bench_switching.py (the switching pendulum), bench_coldstart.py (new processes of `dyadc
simulate`), suite/compile_time.py (the N-link chain) and bench_scale_cartesian.py (the Cartesian
chain). A target without its measurement in this run says so.
"""
from __future__ import annotations

import math
import statistics

FLOOR_RATIO, MATCHED_SPEEDUP, SWITCHING_RATIO = 1.5, 30.0, 5.0
CACHED_S, UNCACHED_S = 0.3, 1.0
CHAIN_N, CHAIN_COMPILE_S, COMPILE_GROWTH, SIMULATE_GROWTH = 128, 5.0, 1.2, 1.5
CARTESIAN_N, CARTESIAN_S = 32, 1.0
OUTPUT_RATIO = 3.0


def section(floor: dict | None, compile_data: dict | None, switching: dict | None,
            coldstart: dict | None, cartesian: dict | None, output_start: dict | None = None) -> list[str]:
    rows = [_floor(floor), _matched(floor), _switching(switching), *_coldstart(coldstart),
            _output_start(output_start), *_chain(compile_data), _cartesian(cartesian)]
    lines = ["## Issue 15 targets", "",
             "Measured in this run (CPU time, medians; the sections below and the files named hold "
             "the details).", "",
             "| target | measured | met |", "|---|---|---|"]
    lines += [f"| {target} | {measured} | {'yes' if met else 'no' if met is not None else 'not measured'} |"
              for target, measured, met, _ in rows]
    gaps = [(target, why) for target, _, met, why in rows if met is False and why]
    if gaps:
        lines += ["", "Where a target is missed, what the profile shows:", ""]
        lines += [f"- **{target}**: {why}" for target, why in gaps]
    return lines + [""]


def _floor(floor: dict | None):
    target = f"excavator, rtol 1e-6, up to 1201 points: `simulate` within {FLOOR_RATIO}x of bare IDAS (VM and C)"
    rows = (floor or {}).get("rows") or []
    if not rows:
        return target, "-", None, ""
    worst = max(rows, key=lambda r: r["ours"] / r["floor"])
    ratio = worst["ours"] / worst["floor"]
    measured = (f"worst {ratio:.2f}x ({worst['codegen']}, {worst['points']} points, all outputs); "
                + ", ".join(f"{r['codegen']} {r['points']}: {r['ours'] / r['floor']:.2f}x" for r in rows))
    why = (f"{worst['codegen']} at {worst['points']} points: the phases table of 'Run time against the floor' "
           f"splits our run; IDAS alone is {worst.get('phases', {}).get('IDAS', float('nan')) * 1e3:.1f} ms "
           f"of {worst['ours'] * 1e3:.1f} ms") if worst.get("phases") else "see 'Run time against the floor'"
    return target, measured, ratio <= FLOOR_RATIO, why


def _matched(floor: dict | None):
    target = f"excavator at matched tip error: at least {MATCHED_SPEEDUP:.0f}x faster than the hand-written scipy Radau model"
    found = ((floor or {}).get("matched") or {}).get("dyadc") or []
    if not found:
        return target, "-", None, ""
    measured = ", ".join(f"{r['contender']} {r['speedup']:.0f}x (rtol {r['rtol']:.0e})" for r in found)
    return target, measured, min(r["speedup"] for r in found) >= MATCHED_SPEEDUP, ""


def _switching(data: dict | None):
    target = f"switching pendulum, 20 s at rtol 1e-8: within {SWITCHING_RATIO:.0f}x of one IDAS run of the angle ODE"
    if not data:
        return target, "-", None, ""
    ratio = data["ours"] / data["floor"]
    matched = data.get("matched")
    measured = f"{ratio:.1f}x at the same rtol" + (
        f", {data['ours'] / matched['time']:.1f}x at matched error (angle ODE at rtol {matched['rtol']:g})"
        if matched else "")
    phases = ", ".join(f"{label} {seconds * 1e3:.0f} ms" for label, seconds in data["phases"].items())
    why = (f"IDAS steps {data['steps']} against {data['floor_steps']} for the floor "
           f"({data['steps'] / data['floor_steps']:.1f}x: {data['calls']} IDAS calls, each switch a cold restart "
           f"at order 1, as CasADi keeps no step history between calls, and rtol "
           f"{data['rtol_after_switch']:g} after the first switch, which buys the accuracy: "
           f"our bob error {data['ours_error']:.1e} against the floor's {data['floor_error']:.1e}); "
           f"under cProfile ({data['profile_total'] * 1e3:.0f} ms): {phases} (docs/numerics.md, "
           f"'Speed of a switching run')")
    return target, measured, ratio <= SWITCHING_RATIO, why


def _coldstart(data: dict | None):
    cached_target = f"cached `dyadc simulate` of the excavator in a new process under {CACHED_S} s"
    uncached_target = f"first, uncached `dyadc simulate` under {UNCACHED_S} s"
    if not data:
        return [(cached_target, "-", None, ""), (uncached_target, "-", None, "")]
    cpu = {label: statistics.median(c for _, c in samples) for label, samples in data["samples"].items() if samples}
    cached, uncached = cpu.get("cached"), cpu.get("uncached")
    why = data.get("why", "") or "docs/cache.md, 'Cold start', holds the stage and import profiles"
    return [(cached_target, f"{cached:.2f} s" if cached is not None else "-",
             None if cached is None else cached < CACHED_S, why),
            (uncached_target, f"{uncached:.2f} s" if uncached is not None else "-",
             None if uncached is None else uncached < UNCACHED_S, why)]


def _output_start(data: dict | None):
    """Issue 28: the cached excavator run writing all 631 signals at 1201 points to CSV, as wall
    medians of new processes against `python -c "import casadi, numpy"` measured beside it."""
    target = (f"cached `dyadc simulate` of the excavator with `--output out.csv` (1201 points) within "
              f"{OUTPUT_RATIO:.0f}x `python -c \"import casadi, numpy\"` (issue 28, new processes, wall medians)")
    if not data:
        return target, "-", None, ""
    wall = {kind: statistics.median(w for w, _ in runs) for kind, runs in data["samples"].items()}
    cpu = {kind: statistics.median(c for _, c in runs) for kind, runs in data["samples"].items()}
    ratio = wall["csv"] / wall["import"]
    measured = (f"{ratio:.2f}x ({wall['csv']:.2f} s against {wall['import']:.2f} s; CPU "
                f"{cpu['csv'] / cpu['import']:.2f}x; without the file {wall['bare'] / wall['import']:.2f}x)")
    why = ("the rows are formatted at `%.17g` by csv_rows.c (Python's `%` without a C compiler), once "
           "per distinct column: bench_output_start.py, docs/runtime.md 'Output files'")
    return target, measured, ratio <= OUTPUT_RATIO, why


def _chain(compile_data: dict | None):
    compile_target = (f"N-link chain: compile under {CHAIN_COMPILE_S:.0f} s at N = {CHAIN_N}, growth at most "
                      f"N^{COMPILE_GROWTH} to N = 256")
    simulate_target = f"N-link chain: simulation growth at most N^{SIMULATE_GROWTH} to N = 256"
    chain = (compile_data or {}).get("chain") or {}
    rows = chain.get("rows") or []
    if not rows:
        return [(compile_target, "-", None, ""), (simulate_target, "-", None, "")]
    by_n = {r["n"]: r for r in rows}
    compile_at = sum(by_n[CHAIN_N][s] for s in ("parse", "flatten", "structure", "lower")) if CHAIN_N in by_n else None

    def local(key):
        if len(rows) < 2:
            return None
        a, b = rows[-2], rows[-1]
        return math.log(b[key] / a[key]) / math.log(b["n"] / a["n"])
    fit = chain.get("fit") or {}
    growth, sim_growth = fit.get("total"), fit.get("simulate")
    last_total, last_sim = local("total"), local("simulate")
    compile_measured = (f"{compile_at:.2f} s at N = {CHAIN_N}; " if compile_at is not None else "") + \
        f"fit N^{growth:.2f}" + (f", N = {rows[-2]['n']} -> {rows[-1]['n']}: N^{last_total:.2f}" if last_total else "")
    compile_met = compile_at is not None and compile_at < CHAIN_COMPILE_S and \
        max(growth, last_total or 0.0) <= COMPILE_GROWTH
    sim_measured = f"fit N^{sim_growth:.2f}" + (f", N = {rows[-2]['n']} -> {rows[-1]['n']}: N^{last_sim:.2f}"
                                                if last_sim else "")
    sim_met = max(sim_growth, last_sim or 0.0) <= SIMULATE_GROWTH
    return [(compile_target, compile_measured, compile_met, "see 'Compile time' and docs/scaling.md"),
            (simulate_target, sim_measured, sim_met, "see docs/scaling.md")]


def _cartesian(row: dict | None):
    target = f"Cartesian N-mass chain at N = {CARTESIAN_N}: under {CARTESIAN_S:.0f} s, the state-set monitor not dominating"
    if not row:
        return target, "-", None, ""
    def listed(value) -> str:
        return "/".join(str(v) for v in value) if isinstance(value, (list, tuple)) else str(value)
    measured = (f"simulate {row['simulate']:.2f} s (compile {row['compile']:.2f} s), {listed(row['steps'])} "
                f"IDAS steps, {listed(row['switches'])} switches, over {row['stop']:g} s")
    return target, measured, row["simulate"] < CARTESIAN_S, "docs/scaling.md, 'Cartesian N-mass chain'"
