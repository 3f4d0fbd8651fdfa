"""The targets of issue 32 item 4 on the native IDAS driver -> docs/benchmarks.md.

    .venv/bin/python benchmarks/bench_native_targets.py [--repeats 3] [--corpus DIR] [--contender PATH]
                                                        [--doc docs/benchmarks.md]

1. The excavator at matched bucket-tip error (suite/native_excavator.py): the native path at least
   30x both scipy Radau contenders, and at most 0.6x a bare CasADi IDAS call on the same DAE on
   CasADi's VM. `--contender PATH` adds a module of benchmarks/contenders' interface.
2. The switching pendulum (bench_switching.py's run on the native driver): at most 5x one IDAS run
   of the angle ODE at matched error.
3. The detailed op-amp (`--corpus DIR`, ElectricalComponents and BlockComponents sources) and the
   event tests (suite/native_events.py): fewer IDAS steps natively than on CasADi's IDAS, the same
   numbers.
CPU medians of interleaved runs in this one process, with the load average at each part's start
and end. The section replaces the block between its markers in the doc (or ends the doc).
"""
from __future__ import annotations

import argparse
import os
import sys
import warnings
from datetime import datetime, timezone
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import bench_switching  # noqa: E402
from compiler.runtime.native import NativeIdasWarning, library, make_integrator  # noqa: E402
from suite import native_events, native_excavator  # noqa: E402
from suite.doc_blocks import write_block  # noqa: E402
from suite.problems import Excavator  # noqa: E402
from suite.targets import SWITCHING_RATIO  # noqa: E402

BEGIN, END = "<!-- issue 32 targets: begin -->", "<!-- issue 32 targets: end -->"
HEADING = "Issue 32 targets: the native IDAS driver"


def load() -> str:
    return " / ".join(f"{v:.1f}" for v in os.getloadavg())


def measure(repeats: int, log, corpus: Path | None = None, contender: Path | None = None,
            excavator: Excavator | None = None) -> dict:
    """Every part, each with the load average (1/5/15 min) at its start and end."""
    data = {"repeats": repeats, "stamp": datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "sundials": library.sundials_version()}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NativeIdasWarning)        # which integrator ran is in each row
        parts = (("excavator", lambda: native_excavator.measure(excavator or Excavator(check_reference=False),
                                                                repeats, log, contender)),
                 ("switching", lambda: bench_switching.measure(repeats, make_integrator)),
                 ("events", lambda: native_events.measure(repeats, log, corpus)))
        for name, part in parts:
            log(f"== issue 32: {name} (load {load()})")
            began = load()
            data[name] = part()
            data[name]["load"] = (began, load())
    return data


def target_rows(data: dict) -> list[tuple[str, str, bool, str]]:
    """(target, measured, met, why where missed)"""
    rows = []
    excavator = data["excavator"]
    for scipy in excavator["scipy"]:
        native = [r for r in excavator["dyadc"] if r["name"] == native_excavator.NATIVE and r["against"] == scipy["name"]]
        measured = ", ".join(f"{r['speedup']:.0f}x (rtol {r['rtol']:.0e}, {r['time'] * 1e3:.1f} ms against "
                             f"{scipy['time'] * 1e3:.0f} ms)" for r in native) or "no rtol matched its tip error"
        measured += "".join(f" (ran on {r['integrator']})" for r in native if r["integrator"] != "native")
        met = bool(native) and native[0]["speedup"] >= native_excavator.TARGET_SPEEDUP and \
            native[0]["integrator"] == "native"
        rows.append((f"excavator at matched tip error: native >= {native_excavator.TARGET_SPEEDUP:.0f}x {scipy['name']}",
                     measured, met, profile_text(excavator["profile"])))
    bare = excavator["bare"]
    rows.append((f"excavator: native <= {native_excavator.TARGET_BARE_RATIO}x a bare CasADi IDAS call on the VM",
                 f"{bare['ratio']:.2f}x (rtol {bare['rtol']:.0e}: {bare['time'] * 1e3:.1f} ms bare)" if bare else "-",
                 bool(bare) and bare["ratio"] <= native_excavator.TARGET_BARE_RATIO, profile_text(excavator["profile"])))
    rows.append(switching_row(data["switching"]))
    for row in data["events"]["rows"]:
        fewer = row["native_steps"] < row["casadi_steps"] and row["integrator"] == "native"
        rows.append((f"{row['case']}: fewer IDAS steps natively, the same numbers",
                     f"{row['native_steps']} against {row['casadi_steps']} steps; same numbers: "
                     f"{'yes' if row['same'] else 'no'}" + ("" if row["integrator"] == "native" else
                                                            f" (ran on {row['integrator']})"), fewer and row["same"],
                     "; ".join([f"`{label}` {a} times natively, {b} on CasADi's IDAS" for label, a, b in row["unmatched"]]
                               + [f"`{name}` differs by at most {value:.2g}" for name, value in row["shown"].items()])
                     + (f"; signals differ up to {row['worst']:.3g} (atol + rtol max|signal|) in `{row['signal']}`"
                        if row["worst"] > native_events.AGREEMENT else "")
                     + (f"; against a run at {native_events.REFERENCE_TIGHTER:g} times smaller tolerances, "
                        f"`{row['judged_signal']}` is off by {row['native_off']:.3g} natively and "
                        f"{row['casadi_off']:.3g} on CasADi's IDAS" if "judged_signal" in row else "")))
    return rows


def switching_row(data: dict) -> tuple[str, str, bool, str]:
    target = f"switching pendulum: native <= {SWITCHING_RATIO:.0f}x one IDAS run of the angle ODE at matched error"
    matched = data["matched"]
    if not matched:
        return target, "no tried rtol of the angle ODE matched the error", False, ""
    ratio = data["ours"] / matched["time"]
    if data["integrator"] != "native":
        return target, f"{ratio:.1f}x, but the run was on {data['integrator']}", False, ""
    stats = data["ours_stats"]
    why = (f"native {data['ours'] * 1e3:.1f} ms, {stats.get('steps')} steps ({data['ours'] / stats.get('steps', 1) * 1e6:.1f} "
           f"us each; rtol {data['rtol_after_switch']:g} after the first switch) in {stats.get('segments')} IDAS calls "
           f"({data['switches']} switches: a restart each), {stats.get('residual_evaluations')} residuals, "
           f"{stats.get('jacobian_evaluations')} Jacobians, {stats.get('newton_iterations')} Newton iterations, "
           f"error {data['ours_error']:.2e}; the angle ODE at rtol {matched['rtol']:g}: {matched['steps']} steps "
           f"({matched['time'] / matched['steps'] * 1e6:.1f} us each), error {matched['error']:.2e}. cProfile of one run ({data['profile_total'] * 1e3:.0f} ms under the "
           "profiler), cumulative: " + ", ".join(f"{label} {seconds * 1e3:.0f} ms"
                                                 for label, seconds in data["phases"].items() if seconds > 0))
    return (target, f"{ratio:.1f}x ({data['ours'] * 1e3:.1f} ms against {matched['time'] * 1e3:.1f} ms)",
            ratio <= SWITCHING_RATIO, why)


def profile_text(profile: list) -> str:
    return ("cProfile of one native run, by own time: "
            + ", ".join(f"`{name}` {own:.1f} ms" for name, own, _ in profile[:6])) if profile else ""


def render(data: dict) -> str:
    rows = target_rows(data)
    loads = ", ".join(f"{name} {data[name]['load'][0]} -> {data[name]['load'][1]}"
                      for name in ("excavator", "switching", "events"))
    lines = [BEGIN, "", f"Measured {data['stamp']} by benchmarks/bench_native_targets.py (native driver: SUNDIALS "
             f"{data['sundials']}; CasADi's own IDAS otherwise), CPU medians of {data['repeats']} interleaved runs "
             f"in one process on a 2-core machine shared with other work; load average (1/5/15 min) at the start "
             f"and end of each part: {loads}.", "", "| target | measured | met |", "|---|---|---|"]
    lines += [f"| {target} | {measured} | {'yes' if met else 'no'} |" for target, measured, met, _ in rows]
    missed = [(target, why) for target, _, met, why in rows if not met and why]
    if missed:
        lines += ["", "Where a target is missed, the gap and what the profile and IDAS's counters show:", ""]
        lines += [f"- **{target}**: {why}" for target, why in missed]
    lines += ["", "### The excavator at matched tip error, native and CasADi paths", ""]
    lines += native_excavator.render(data["excavator"])
    lines += ["### The detailed op-amp and the event tests, native against CasADi's IDAS (both on C)", ""]
    lines += native_events.render(data["events"])
    return "\n".join(lines + [END])


def write_doc(section: str, doc: Path) -> None:
    write_block(doc, section, BEGIN, END, heading=HEADING)


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--corpus", type=Path, default=None,
                        help="a folder with ElectricalComponents/dyad and BlockComponents/dyad (the op-amp)")
    parser.add_argument("--contender", type=Path, default=None,
                        help="another excavator contender: a module with run(method, rtol, atol) -> dict")
    parser.add_argument("--doc", type=Path, default=ROOT / "docs" / "benchmarks.md")
    args = parser.parse_args(argv)
    if library.driver_library()[0] is None:
        print(f"error: the native IDAS driver is not built: {library.driver_library()[1]}; run `make install`",
              file=sys.stderr)
        return 2
    section = render(measure(args.repeats, lambda line: print(line, flush=True), args.corpus, args.contender))
    write_doc(section, args.doc)
    print(section)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
