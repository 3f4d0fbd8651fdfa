"""`dyadc sweep`: the command line over compiler.sweep.sweep."""
from __future__ import annotations

import sys
from pathlib import Path

from compiler.errors import DyadError


def main_sweep(args) -> int:
    from compiler.sweep.api import SweepInterrupted, SweepOptions, sweep
    from compiler.sweep.design import grid_design, parse_assignment, sampled_design
    from compiler.sweep.writers import sibling, table_format

    # Everything that can be checked before the compile is checked first.
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
    axes = [parse_assignment(text) for text in args.params]
    design = (sampled_design(axes, args.samples, args.method, args.seed) if args.samples is not None
              else grid_design(axes))
    partial = sibling(args.output, "partial") if args.output else Path("sweep.partial.csv")
    options = SweepOptions(stop=args.stop, start=args.start, rtol=args.rtol, atol=args.atol,
                           points=args.points, variables=args.vars, metrics=args.metrics,
                           lib_dirs=args.lib, serial=args.serial, workers=args.workers,
                           batch_size=args.batch_size, progress=args.progress,
                           partial_output=partial, recompile=args.recompile)
    try:
        result = sweep(args.model, design, options, scheduler=args.scheduler)
    except SweepInterrupted as stop:
        where = (f"; the {len(stop.partial)} finished samples are in {stop.path} and "
                 f"{sibling(stop.path, 'samples')}" if stop.path else "; no sample had finished")
        print(f"interrupted: {stop}{where}", file=sys.stderr)
        return 130

    print(result.summary(), file=sys.stderr)
    stats = result.stats
    engine = (f"{stats.get('workers')} Dask workers ({stats.get('scheduler')}), "
              f"{stats.get('batch_size')} samples per task" if stats.get("engine") == "dask" else "serial")
    models = stats.get("compiled_models", 1)
    print(f"ran on {engine}" + (f", {models} compiled models (--recompile)" if models > 1 else ""),
          file=sys.stderr)
    if args.output:
        trajectories, samples = result.write(args.output)
        print(f"wrote {trajectories} and {samples}", file=sys.stderr)
    if args.plot:
        print(f"wrote {result.plot(args.plot)}", file=sys.stderr)
    if not args.output:
        _print_samples(result)
    return 0 if result.succeeded else 1


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
