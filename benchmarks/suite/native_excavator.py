"""Issue 32 item 4, the excavator: dyadc on the native IDAS driver (and on CasADi's IDAS, for
reference) against both scipy Radau contenders at matched bucket-tip error, and against a bare
CasADi IDAS call on the same DAE on CasADi's VM.

The contenders (benchmarks/contenders/scipy_excavator.py on tests/reference/excavator_minimal.py)
run at rtol 1e-6 (suite/matched.py): `make bench`'s own, one solve_ivp call over 12 s, and the
reference model as it is written, restarted at its waypoints; a third, any module of the
contenders' interface, can be named by path. Each dyadc contender runs at the loosest rtol whose
tip error is no worse than each scipy contender's (suite/matched.py's rule); the bare call runs at
the rtol the native path needed. Every timed run is interleaved with the others in this one
process (CPU medians, bench_native_idas.cpu_runs).
"""
from __future__ import annotations

import cProfile
import pstats
from pathlib import Path

import bench_native_idas
from compiler.runtime.native import make_integrator
from compiler.runtime.integrator import COUNTERS
from suite.contenders import DyadcContender, Failed, ScipyContender
from suite.matched import RTOLS, SCIPY_METHOD, SCIPY_RTOL, cpu_solve, loosest_matching, tip_error
from suite.problems import Problem, load_path

NATIVE = "dyadc (C, native IDAS)"
BARE = "bare CasADi IDAS call, VM"
TARGET_SPEEDUP, TARGET_BARE_RATIO = 30.0, 0.6


def scipy_contenders(problem: Problem, extra: Path | None = None) -> list[ScipyContender]:
    """Both scipy Radau contenders, and the one at `extra` (a module of the contenders' interface)."""
    made = [ScipyContender(problem, SCIPY_METHOD, variant="make bench's: one solve_ivp call"),
            ScipyContender(problem, SCIPY_METHOD, options={"split_at_waypoints": True},
                           variant="the reference model as written: restarted at its waypoints")]
    if extra is not None:
        made.append(ScipyContender(problem, SCIPY_METHOD, options={}, variant=extra.stem,
                                   module=load_path(f"_bench_extra_{extra.stem}", extra)))
    return made


def dyadc_contenders(problem: Problem) -> tuple[list[DyadcContender], list[str]]:
    """The native path first, then CasADi's IDAS on C and on the VM; why any could not be made."""
    made, notes = [], []
    for codegen, integrator, label in (("c", make_integrator, "native IDAS"), ("c", "casadi", "CasADi IDAS"),
                                       ("vm", "casadi", "CasADi IDAS")):
        try:
            made.append(DyadcContender(problem, codegen, integrator, label))
        except Failed as err:
            notes.append(f"dyadc ({codegen.upper()}, {label}) unavailable: {err}")
    return made, notes


def measure(problem: Problem, repeats: int, log, extra: Path | None = None,
            rtols=RTOLS) -> dict:
    """{"scipy": [{name, tip, time}], "dyadc": [{name, against, rtol, tip, time, speedup, stats}],
    "bare": {rtol, time, stats, ratio}, "profile": [...], "notes": [...]}"""
    scipys = scipy_contenders(problem, extra)
    targets = {}
    for scipy in scipys:
        targets[scipy.name] = tip_error(problem, cpu_solve(scipy, SCIPY_RTOL, problem.atol_ratio)[1])
        log(f"  {scipy.name} rtol {SCIPY_RTOL:.0e}: tip error {targets[scipy.name]:.2e} m")
    dyadcs, notes = dyadc_contenders(problem)
    matches = []
    for dyadc in dyadcs:
        for scipy in scipys:
            found = loosest_matching(problem, dyadc, targets[scipy.name], rtols)
            notes += found["notes"]
            if found["rtol"] is not None:
                matches.append({"name": dyadc.name, "against": scipy.name, "rtol": found["rtol"],
                                "tip": found["tip"], "contender": dyadc})
                log(f"  {dyadc.name} against {scipy.name}: rtol {found['rtol']:.0e}, tip {found['tip']:.2e} m")
    runs = {s.name: timed_solve(s, SCIPY_RTOL, problem) for s in scipys}
    for match in matches:
        runs.setdefault(run_label(match), timed_solve(match["contender"], match["rtol"], problem))
    native_rtols = sorted({m["rtol"] for m in matches if m["name"] == NATIVE})
    vm = next((d for d in dyadcs if d.codegen == "vm"), None)
    bare_rtol = native_rtols[-1] if native_rtols and vm is not None else None    # the loosest
    if bare_rtol is not None:
        runs[BARE] = bench_native_idas.bare_call(vm.compilation.model, problem.stop, len(problem.grid), bare_rtol)
    timed = bench_native_idas.cpu_runs(runs, repeats)
    return summary(problem, targets, matches, timed, bare_rtol, notes, log)


def run_label(match: dict) -> str:
    return f"{match['name']} at rtol {match['rtol']:.0e}"


def timed_solve(contender, rtol: float, problem: Problem):
    """A call that solves once and returns what it keeps of the run (dyadc: its statistics)."""
    def run():
        cpu_solve(contender, rtol, problem.atol_ratio)
        return getattr(contender, "last_stats", None)
    return run


def summary(problem, targets, matches, timed, bare_rtol, notes, log) -> dict:
    scipy_rows = [{"name": name, "tip": tip, "time": timed[name][0]} for name, tip in targets.items()]
    rows = []
    for match in matches:
        seconds, stats = timed[run_label(match)]
        against = timed[match["against"]][0]
        rows.append({**{k: match[k] for k in ("name", "against", "rtol", "tip")}, "time": seconds,
                     "speedup": against / seconds, "stats": counters(stats),
                     "integrator": (stats or {}).get("integrator")})
        log(f"  {match['name']} (rtol {match['rtol']:.0e}): {seconds * 1e3:.1f} ms against "
            f"{match['against']} {against * 1e3:.0f} ms: {against / seconds:.1f}x")
    bare = None
    if bare_rtol is not None:
        seconds, result = timed[BARE]
        native = next(r for r in rows if r["name"] == NATIVE and r["rtol"] == bare_rtol)
        bare = {"rtol": bare_rtol, "time": seconds, "ratio": native["time"] / seconds,
                "stats": {COUNTERS[k]: v for k, v in result.stats["idas"].items() if k in COUNTERS}}
        log(f"  {BARE} at rtol {bare_rtol:.0e}: {seconds * 1e3:.1f} ms; native {bare['ratio']:.2f}x")
    native_rows = [r for r in rows if r["name"] == NATIVE]
    profile = python_profile(next(m for m in matches if m["name"] == NATIVE), problem) if native_rows else []
    return {"scipy": scipy_rows, "dyadc": rows, "bare": bare, "profile": profile, "notes": notes,
            "scipy_rtol": SCIPY_RTOL}


def counters(stats: dict | None) -> dict:
    """IDAS's counters of a dyadc run by the runtime's names (Result.stats)."""
    names = (*COUNTERS.values(), "segments")
    return {name: stats[name] for name in names if stats and name in stats}


def python_profile(match: dict, problem: Problem, top: int = 8) -> list[tuple[str, float, float]]:
    """cProfile of one native run: (function, own ms, cumulative ms) of the `top` by own time."""
    profiler = cProfile.Profile()
    profiler.runcall(cpu_solve, match["contender"], match["rtol"], problem.atol_ratio)
    stats = pstats.Stats(profiler).stats
    rows = sorted(stats.items(), key=lambda item: item[1][2], reverse=True)[:top]
    return [(f"{Path(key[0]).name}:{key[1]}({key[2]})", row[2] * 1e3, row[3] * 1e3) for key, row in rows]


def render(data: dict) -> list[str]:
    """The excavator's tables (markdown lines)."""
    lines = [f"Each scipy contender at rtol = atol = {data['scipy_rtol']:.0e} (atol scaled per state by "
             "the model); each dyadc run at the loosest rtol (atol = rtol) whose bucket-tip error (max over "
             "the 1201 points of the distance to the reference tip) is no worse than that contender's:", "",
             "| run | against | rtol | tip error [m] | CPU | speed-up | IDAS steps | residuals | Jacobians "
             "| Newton iterations |", "|---|---|---|---|---|---|---|---|---|---|"]
    for s in data["scipy"]:
        lines.append(f"| {s['name']} | | {data['scipy_rtol']:.0e} | {s['tip']:.2e} | {s['time'] * 1e3:.0f} ms "
                     "| 1 | | | | |")
    for r in data["dyadc"]:
        st = r["stats"]
        lines.append(f"| {r['name']} | {r['against']} | {r['rtol']:.0e} | {r['tip']:.2e} | "
                     f"{r['time'] * 1e3:.1f} ms | **{r['speedup']:.0f}x** | {st.get('steps', '')} | "
                     f"{st.get('residual_evaluations', '')} | {st.get('jacobian_evaluations', '')} | "
                     f"{st.get('newton_iterations', '')} |")
    bare = data["bare"]
    if bare:
        st = bare["stats"]
        lines += ["", f"The bare CasADi IDAS call on the same DAE on CasADi's VM (bench_floor.py's floor, at the "
                      f"native run's rtol {bare['rtol']:.0e}): {bare['time'] * 1e3:.1f} ms, {st.get('steps')} steps, "
                      f"{st.get('residual_evaluations')} residuals, {st.get('jacobian_evaluations')} Jacobians, "
                      f"{st.get('newton_iterations')} Newton iterations; the native run takes "
                      f"**{bare['ratio']:.2f}x** its CPU time."]
    lines += [f"- {note}" for note in data["notes"]]
    return lines + [""]
