"""`dyadc run ANALYSIS`: run a Dyad `analysis` block (TransientAnalysis) and write its result.

The result goes to `--output FILE` (the extension picks the format, as for `dyadc simulate`), by
default `<AnalysisName>.csv` in the current folder; `-p NAME=VALUE` overrides an analysis parameter
(or, when the analysis has none of that name, a parameter of its model).
"""
from __future__ import annotations

import argparse
import sys

from compiler.cli.arguments import add_lib_argument, add_params_argument, add_units_argument

RUN_HELP = ("run an `analysis` block (TransientAnalysis; LinearAnalysis, ClosedLoopAnalysis, "
            "ClosedLoopSensitivityAnalysis) and write its result (CSV, or JSON and plots)")


def add_run(sub) -> None:
    p = sub.add_parser("run", help=RUN_HELP, description=RUN_HELP + ". ANALYSIS is "
                       "path/File.dyad:Name, path/File.dyad (its one analysis) or a qualified name.")
    p.add_argument("analysis", metavar="ANALYSIS", help="analysis file:Name or qualified name")
    add_lib_argument(p)
    add_params_argument(p, "override an analysis parameter, else a model parameter (repeatable)")
    p.add_argument("--points", type=int, default=501, metavar="N",
                   help="output points when the analysis gives no saveat (default 501)")
    p.add_argument("--vars", nargs="+", metavar="NAME", help="signals to write (default: all)")
    p.add_argument("--output", metavar="FILE",
                   help="result file (default <AnalysisName>.csv); .csv, .parquet, .mat, .npz")
    p.add_argument("--plot", metavar="FILE.png", help="also plot the result, one subplot per unit")
    p.add_argument("--max-output-values", type=int, metavar="N",
                   help="refuse runs storing more than N output values (as dyadc simulate)")
    add_units_argument(p)
    p.set_defaults(run=run_analysis)


ADDERS = {"run": add_run}


def run_analysis(args: argparse.Namespace) -> int:
    from compiler.cli import options
    from compiler.analysis.transient import FIELDS, find_analysis, read_transient
    from compiler.api import simulate_compiled
    from compiler.cli.outputs import check_simulate_outputs, listed, write_result
    from compiler.cli.simulate import code_named, integrator_named
    from compiler.errors import DyadError
    from compiler.model.flatten import flatten_resolved
    from compiler.model.library import Library
    from compiler.pipeline import compile_flat
    from compiler.testing.golden import initialization_notes

    overrides = [options.parse_override(text) for text in args.params]
    limit = options.max_output_values(args.max_output_values)
    library = Library(args.lib)
    resolved = find_analysis(args.analysis, library)
    from compiler.analysis.linear_analyses import linear_kind
    if linear_kind(resolved, library):
        from compiler.cli.linear_run import main_linear_run
        return main_linear_run(args, resolved, library, overrides)
    run = read_transient(resolved, library, {o.name: o.value for o in overrides})
    for o in overrides:
        if o.unit is not None and (o.name in run.parameters or o.name in FIELDS):
            raise DyadError(f"-p {o.text}: `{o.name}` belongs to the analysis; give a plain number")
    output = args.output or f"{resolved.definition.name}.csv"
    check_simulate_outputs(output, args.plot)
    saveat = None
    if run.saveat > 0:
        saveat = options.SaveAt(f"saveat = {run.saveat:g}", first=run.start, step=run.saveat,
                                last=run.stop, every=True)
        times = saveat.count()
    else:
        options.check_points(args.points)
        times = args.points
    options.check_output_size(times, 0, limit, f"analysis {resolved.definition.name}")

    compilation = compile_flat(flatten_resolved(run.model, library))
    model = compilation.model
    options.check_output_size(times, len(model.output_names), limit,
                              f"{times:,} output times of {resolved.definition.name}")
    units = model.metadata.get("units", {})
    model_overrides = [o for o in overrides if o.name not in run.parameters and o.name not in FIELDS]
    params = options.convert_overrides(model_overrides, model.parameters, units)
    names = options.chosen_signals(args.vars, model.output_names)
    for note in list(run.notes) + initialization_notes(compilation):     # after the options' checks
        print(f"note: {note}", file=sys.stderr)
    result = simulate_compiled(compilation, run.stop, start=run.start, rtol=run.reltol,
                               atol=run.abstol, points=args.points,
                               saveat=None if saveat is None else saveat.grid(), params=params,
                               max_step=run.dtmax if run.dtmax > 0 else None)
    paths = write_result(result, names or result.names, units, resolved.definition.name, output, args.plot)
    stats = result.stats
    written = listed(paths)
    print(f"ran {resolved.definition.name} ({run.model_name} from {run.start:g} to {run.stop:g} s, "
          f"reltol {run.reltol:g}, abstol {run.abstol:g}) {integrator_named(stats)}: "
          f"{stats.get('steps')} steps, compile "
          f"{stats.get('compile_time', 0):.2f} s, run {stats.get('run_time', 0):.2f} s "
          f"{code_named(stats)}; wrote "
          f"{written}", file=sys.stderr)
    return 0
