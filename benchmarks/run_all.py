"""`make bench`: work-precision diagrams and compile-time scaling -> docs/benchmarks.md + PNGs.

    .venv/bin/python benchmarks/run_all.py            # full run (target < 15 min on 2 cores)
    .venv/bin/python benchmarks/run_all.py --quick    # fewer tolerances, smaller budgets (~3 min)
    .venv/bin/python benchmarks/run_all.py --only pendulum,andrews --no-compile --out /tmp/bench

Everything is measured in this one process except the compile-time stages, which run in fresh
processes so that imports and parser construction are included.
"""
from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from suite import compile_time, machine, plots, report  # noqa: E402
from suite.problems import all_problems  # noqa: E402
from suite.targets import section  # noqa: E402
from suite.timing import Budget  # noqa: E402
from suite.workprecision import FULL_TOLERANCES, QUICK_TOLERANCES, run_problem  # noqa: E402

CHAIN_SIZES = [1, 2, 4, 8, 16, 32, 64, 128, 256]


def settings_for(quick: bool) -> dict:
    if quick:
        return {"quick": True, "tolerances": QUICK_TOLERANCES, "repeats": 3, "repeat_window": 3.0,
                "budget": 10.0, "excavator_budget": 20.0, "excavator_compiles": 1, "chain_budget": 20.0}
    return {"quick": False, "tolerances": FULL_TOLERANCES, "repeats": 5, "repeat_window": 8.0,
            "budget": 25.0, "excavator_budget": 60.0, "excavator_compiles": 3, "chain_budget": 340.0}


def log(message: str) -> None:
    print(message, flush=True)


def cold_start(repeat: int) -> dict:
    """CPU medians of new `dyadc simulate` processes of the excavator (a snapshot of the sources, as
    bench_coldstart.py measures it) and the stages of an uncached one."""
    import bench_coldstart
    with tempfile.TemporaryDirectory(prefix="dyadc-bench-sources-") as copy:
        bench_coldstart.SOURCES = bench_coldstart.snapshot(Path(copy))
        samples = bench_coldstart.measure(bench_coldstart.EXCAVATOR, 12.0, repeat)
        stages = bench_coldstart.stage_profile(bench_coldstart.EXCAVATOR, 12.0)
    why = ("stages of an uncached run, wall s: " + ", ".join(f"{k} {v:.3f}" for k, v in stages.items())
           + " (docs/cache.md, 'Cold start')")
    return {"samples": samples, "why": why}


def output_start(repeat: int) -> dict:
    """Wall and CPU medians of new processes: `import casadi, numpy`, a cached `dyadc simulate` of
    the excavator, and the same writing a CSV (bench_output_start.py, issue 28)."""
    import bench_coldstart
    import bench_output_start
    with tempfile.TemporaryDirectory(prefix="dyadc-bench-sources-") as copy:
        bench_coldstart.SOURCES = bench_coldstart.snapshot(Path(copy))
        return {"samples": bench_output_start.measure(repeat)}


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer tolerances, smaller budgets")
    parser.add_argument("--only", default="", help="comma-separated problems (excavator, pendulum, swinging, andrews, robertson)")
    parser.add_argument("--no-compile", action="store_true", help="skip the compile-time measurements")
    parser.add_argument("--no-sweep", action="store_true", help="skip the sweep benchmark (bench_sweep.py)")
    parser.add_argument("--no-accuracy", action="store_true",
                        help="skip the state-selection accuracy table (bench_accuracy.py, docs/numerics.md)")
    parser.add_argument("--no-floor", action="store_true", help="skip the floor benchmark (bench_floor.py) and the "
                                                                "matched-tip-error comparison")
    parser.add_argument("--no-targets", action="store_true", help="skip the cold-start and Cartesian-chain "
                                                                  "measurements of the issue-15 targets")
    parser.add_argument("--no-linear", action="store_true",
                        help="skip linearizing the excavator from the cache (bench_linearize.py, docs/analysis.md)")
    parser.add_argument("--no-units", action="store_true",
                        help="skip the unit check's cost on the excavator's uncached compile (bench_units.py)")
    parser.add_argument("--no-native", action="store_true",
                        help="skip the issue-32 targets on the native IDAS driver (bench_native_targets.py)")
    parser.add_argument("--corpus", type=Path, default=None,
                        help="a folder with ElectricalComponents/dyad and BlockComponents/dyad: the detailed "
                             "op-amp of the issue-32 targets")
    parser.add_argument("--no-fmu", action="store_true",
                        help="skip FMPy's runs of the excavator's FMUs (bench_fmu.py, docs/fmu.md)")
    parser.add_argument("--out", default=str(ROOT / "docs"), help="folder for benchmarks.md (PNGs go to <out>/benchmarks/)")
    args = parser.parse_args(argv)
    os.environ.setdefault("OMP_NUM_THREADS", "1")      # scipy/numpy threads would steal the other core
    began = time.perf_counter()
    settings = settings_for(args.quick)
    out = Path(args.out)
    png_dir = out / "benchmarks"
    png_dir.mkdir(parents=True, exist_ok=True)
    info = machine.describe()
    log(f"machine: {info['CPU']}, {info['cores (nproc)']} cores, load {info['load average at start (1/5/15 min)']}")

    wanted = {w for w in args.only.split(",") if w}
    problems = [p for p in all_problems(check_reference=not args.quick) if not wanted or p.key in wanted]
    runs, pngs = [], {}
    for problem in problems:
        log(f"== {problem.title}")
        if problem.key == "excavator":
            problem.reference                                         # noqa: B018 - computed before the timings
            log(f"  reference computed in {problem.reference_info['seconds']:.1f} s")
        budget_s = settings["excavator_budget"] if problem.key == "excavator" else settings["budget"]
        budget = Budget(budget_s, settings["repeats"], settings["repeat_window"])
        run = run_problem(problem, settings["tolerances"], budget, log)
        runs.append(run)
        pngs[problem.key] = f"benchmarks/work_precision_{problem.key}.png"
        plots.work_precision_png(run, out / pngs[problem.key])
        log(f"  {time.perf_counter() - began:.0f} s elapsed")

    floor: dict = {}
    if not args.no_floor:
        log("== floor: simulate vs a bare IDAS run (bench_floor.py)")
        import bench_floor
        floor["rows"] = bench_floor.measure(settings["repeats"], log=lambda line: log("  " + line))
        excavator = next((r.problem for r in runs if r.problem.key == "excavator"), None)
        if excavator is not None:
            log("== matched tip error: dyadc vs scipy Radau at rtol 1e-6")
            from suite.matched import matched_tip_error
            floor["matched"] = matched_tip_error(excavator, settings["repeats"], log)

    native_section = ""
    if not args.no_native:
        log("== issue 32: the native IDAS driver against its targets (bench_native_targets.py)")
        import bench_native_targets
        excavator = next((r.problem for r in runs if r.problem.key == "excavator"), None)
        native_section = bench_native_targets.render(bench_native_targets.measure(
            settings["repeats"], lambda line: log("  " + line), args.corpus, excavator=excavator))

    compile_data: dict = {}
    if not args.no_compile:
        log("== compile time")
        compile_data["excavator"] = compile_time.excavator_stages(settings["excavator_compiles"], log)
        compile_data["chain"] = compile_time.chain_scaling(CHAIN_SIZES, settings["chain_budget"], log)
        chain = compile_data["chain"]
        if chain["rows"]:
            pngs["compile"] = "benchmarks/compile_time_chain.png"
            plots.compile_scaling_png(chain["rows"], compile_time.STAGES, chain["fit"], out / pngs["compile"])

    if not args.no_sweep:
        log("== sweep (serial vs LocalCluster, its table goes into sweeps.md)")
        import bench_sweep
        bench_sweep.main(["--samples", "40" if args.quick else "200", "--doc", str(out / "sweeps.md")])

    switching = None
    if not args.no_accuracy:
        log("== accuracy of dynamic state selection and error control (its table goes into numerics.md)")
        import bench_accuracy
        bench_accuracy.main((["--quick"] if args.quick else []) + ["--doc", str(out / "numerics.md")])
        log("== the switching pendulum against one IDAS run of its angle ODE (numerics.md)")
        import bench_switching
        switching = bench_switching.measure(settings["repeats"])
        bench_switching.write_doc(bench_switching.render(switching, settings["repeats"]), out / "numerics.md")

    coldstart = cartesian = with_output = None
    if not args.no_targets:
        log("== cold start: dyadc simulate in new processes (bench_coldstart.py)")
        coldstart = cold_start(3 if args.quick else 5)
        log("== cold start writing a CSV, beside `import casadi, numpy` (bench_output_start.py)")
        with_output = output_start(3 if args.quick else 7)
        log("== Cartesian chain N = 32 (bench_scale_cartesian.py)")
        import bench_scale_cartesian
        cartesian = list(bench_scale_cartesian.cartesian_rows(32, 2.0, 3, "tests"))[-1]
    if not args.no_linear:
        log("== linearizing the excavator from the cache (its table goes into analysis.md)")
        import bench_linearize
        bench_linearize.main(["--repeats", "5" if args.quick else "15", "--doc", str(out / "analysis.md")])
    units_section = ""
    if not args.no_units:
        log("== the unit check's cost on the excavator's uncached compile (bench_units.py)")
        import bench_units
        units_section = bench_units.render(bench_units.measure(3 if args.quick else 7))
    fmu_section = ""
    if not args.no_fmu:
        log("== the excavator's FMUs in FMPy beside dyadc's run (bench_fmu.py; its table also goes into fmu.md)")
        import bench_fmu
        fmu_section = bench_fmu.render(bench_fmu.measure(repeats=3 if args.quick else 5,
                                                         evaluations=5000 if args.quick else 20000))
        from suite.doc_blocks import write_block
        write_block(out / "fmu.md", fmu_section, bench_fmu.BEGIN, bench_fmu.END, heading="Speed")
        fmu_section = "## FMU export (bench_fmu.py)\n\n" + fmu_section + "\n"
    targets = section(floor, compile_data, switching, coldstart, cartesian, with_output)

    elapsed = time.perf_counter() - began
    text = report.render(info, runs, compile_data, pngs, settings, elapsed, floor, targets)
    native_part = f"\n## {bench_native_targets.HEADING}\n\n{native_section}\n" if native_section else ""
    (out / "benchmarks.md").write_text(text + ("\n" + units_section if units_section else "") + native_part
                                       + ("\n" + fmu_section if fmu_section else ""), encoding="utf-8")
    log(f"wrote {out / 'benchmarks.md'} in {elapsed / 60:.1f} min")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
