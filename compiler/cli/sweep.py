"""`dyadc sweep`: the command line over compiler.sweep.sweep (docs/sweeps.md)."""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from compiler.cli.arguments import add_model_arguments
from compiler.errors import DyadError


def add_sweep(sub) -> None:
    p = sub.add_parser("sweep", help="run a model over a grid or random samples of its parameters "
                                     "(Dask or --serial); see docs/sweeps.md")
    add_model_arguments(p)
    p.add_argument("--start", type=float, default=0.0, metavar="T0")
    p.add_argument("--stop", type=float, required=True, metavar="T")
    p.add_argument("--rtol", type=float, default=1e-6, metavar="R")
    p.add_argument("--atol", type=float, default=1e-6, metavar="A")
    p.add_argument("--points", type=int, default=501, metavar="N", help="output points (default 501)")
    p.add_argument("-p", dest="params", action="append", default=[], metavar="NAME=AXIS",
                   help="START:STOP:COUNT or [V1,V2] (grid axes), LOW:HIGH, uniform(a,b), "
                        "loguniform(a,b), normal(mean,std) (with --samples), or VALUE (fixed)")
    p.add_argument("--samples", type=int, metavar="N", help="draw N samples instead of a grid")
    p.add_argument("--method", choices=["lhs", "random"], default="lhs",
                   help="sampling for --samples: Latin hypercube (default) or plain random")
    p.add_argument("--seed", type=int, default=None, metavar="S", help="seed for --samples")
    p.add_argument("--vars", nargs="+", metavar="NAME", help="signals to record (default: the states)")
    p.add_argument("--metrics", nargs="+", default=[], metavar="EXPR",
                   help="per-sample scalars, e.g. 'max(abs(tip.y))' or 'peak=max(soil.F_y)'")
    p.add_argument("--output", metavar="FILE.parquet|FILE.csv",
                   help="trajectories; the per-sample table goes to FILE.samples.EXT")
    p.add_argument("--plot", metavar="FILE.png", help="fan charts of the first three --vars over time, "
                                                      "scatters of each metric against each swept parameter")
    p.add_argument("--serial", action="store_true", help="run the samples here, one after another (no Dask)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="an existing Dask scheduler, e.g. tcp://host:8786 (default $DASK_SCHEDULER_ADDRESS, "
                        "else a local cluster)")
    p.add_argument("--workers", type=int, metavar="N", help="local cluster size (default: one per core)")
    p.add_argument("--recompile", action="store_true",
                   help="allow structural parameters (array sizes, branches): compile once per distinct value")
    p.add_argument("--batch-size", type=int, metavar="N", help="samples per Dask task (default: sized "
                                                               "so task overhead stays under 10%%)")
    p.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                   help="progress bar on stderr (default: when stderr is a terminal)")
    p.set_defaults(run=run_sweep)


ADDERS = {"sweep": add_sweep}


def run_sweep(args) -> int:
    from compiler.cli.progress import SweepProgress
    from compiler.sweep.api import SweepInterrupted, SweepOptions, sweep
    from compiler.sweep.design import grid_design, parse_assignment, sampled_design
    from compiler.sweep.writers import sibling

    check_options(args)                # everything that can be checked before the compile
    axes = [parse_assignment(text) for text in args.params]
    design = (sampled_design(axes, args.samples, args.method, args.seed) if args.samples is not None
              else grid_design(axes))
    partial = sibling(args.output, "partial") if args.output else Path("sweep.partial.csv")
    bar = SweepProgress(len(design), args.progress)
    options = SweepOptions(stop=args.stop, start=args.start, rtol=args.rtol, atol=args.atol,
                           points=args.points, variables=args.vars, metrics=args.metrics,
                           lib_dirs=args.lib, serial=args.serial, workers=args.workers,
                           batch_size=args.batch_size, partial_output=partial, recompile=args.recompile,
                           on_sample=lambda outcome: bar.advance(1, 0 if outcome.ok else 1))
    try:
        try:
            result = sweep(args.model, design, options, scheduler=args.scheduler)
        finally:
            bar.close()
    except SweepInterrupted as stop:
        where = (f"; the {len(stop.partial)} finished samples are in {stop.path} and "
                 f"{sibling(stop.path, 'samples')}" if stop.path else "; no sample had finished")
        print(f"interrupted: {stop}{where}", file=sys.stderr)
        return 130
    report(result, args)
    if result.succeeded:
        return 0
    print(f"error: no sample of {len(result.design)} succeeded (the reasons are above)", file=sys.stderr)
    return 1


def check_options(args) -> None:
    from compiler.sweep.writers import table_format
    if args.output:
        table_format(args.output)
    if args.samples is None and args.seed is not None:
        raise DyadError("--seed only applies to --samples", hint="add --samples N, or drop --seed")
    if args.workers is not None and args.workers < 1:
        raise DyadError(f"--workers must be at least 1, got {args.workers}")
    if args.batch_size is not None and args.batch_size < 1:
        raise DyadError(f"--batch-size must be at least 1, got {args.batch_size}")
    if args.serial and args.scheduler:
        raise DyadError("--serial runs here without Dask; --scheduler names a Dask cluster",
                        hint="give one of them")


def report(result, args) -> None:
    """The summary and the engine (and the integrator) on stderr; the files written, or the
    per-sample table."""
    from compiler.cli.simulate import integrator_named
    print(result.summary(), file=sys.stderr)
    stats = result.stats
    engine = (f"{stats.get('workers')} Dask workers ({stats.get('scheduler')}), "
              f"{stats.get('batch_size')} samples per task" if stats.get("engine") == "dask" else "serial")
    models = stats.get("compiled_models", 1)
    ran = f", {integrator_named(stats)}" if stats.get("integrator") else ""
    print(f"ran on {engine}" + (f", {models} compiled models (--recompile)" if models > 1 else "") + ran,
          file=sys.stderr)
    if args.output:
        trajectories, samples = result.write(args.output)
        print(f"wrote {trajectories} and {samples}", file=sys.stderr)
    if args.plot:
        print(f"wrote {result.plot(args.plot)}", file=sys.stderr)
    if not args.output:
        _print_samples(result)


def _print_samples(result) -> None:
    """Without --output: the per-sample table on stdout (parameters, status, metrics)."""
    table = result.samples()
    names = ["sample", *result.parameters, "status", *result.metric_labels]
    widths = [max(12, len(n)) for n in names]
    print("  ".join(f"{n:>{w}}" for n, w in zip(names, widths)))
    for i in range(len(table["sample"])):
        cells = []
        for n, w in zip(names, widths):
            value = table[n][i]
            cells.append(f"{value:>{w}}" if isinstance(value, str) or n == "sample" else f"{value:>{w}.6g}")
        print("  ".join(cells))
