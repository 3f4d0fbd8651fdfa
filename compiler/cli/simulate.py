"""`dyadc simulate`: options checked before any compiling, the compiled model from the cache or the
compiler, the result written or its final values printed."""
from __future__ import annotations

import os
import sys

from compiler.cli.arguments import add_model_arguments, add_params_argument
from compiler.errors import Note, SimulationError


def add_simulate(sub) -> None:
    p = sub.add_parser("simulate", help="compile and simulate a model")
    add_model_arguments(p)
    p.add_argument("--start", type=float, default=0.0, metavar="T0", help="start time (default 0)")
    p.add_argument("--stop", type=float, required=True, metavar="T", help="stop time, after --start")
    p.add_argument("--rtol", type=float, default=1e-6, metavar="R", help="relative tolerance > 0 (default 1e-6)")
    p.add_argument("--atol", type=float, default=1e-6, metavar="A", help="absolute tolerance > 0 (default 1e-6)")
    grid = p.add_mutually_exclusive_group()
    grid.add_argument("--points", type=int, default=501, metavar="N",
                      help="N evenly spaced output times (default 501)")
    grid.add_argument("--saveat", metavar="TIMES",
                      help="output times: DT (every DT, --stop included), a list T1,T2,... or a range "
                           "FIRST:STEP:LAST")
    add_params_argument(p, "override a parameter by dotted path, optionally with a unit converted to the "
                           "declared one, e.g. -p L=100mm (repeatable)")
    p.add_argument("--vars", nargs="+", metavar="NAME", help="signals to write (default: all); a name "
                   "with * or ? is a pattern, e.g. 'body.*' ([ stays an index: r[1])")
    p.add_argument("--output", metavar="FILE",
                   help="write the result; the extension picks the format: .csv, .parquet, .mat, .npz")
    p.add_argument("--plot", metavar="FILE.png", help="plot the result, one subplot per unit "
                                                      "(.png, .pdf, .svg, ...)")
    p.add_argument("--events", metavar="FILE.csv", help="write the located state events as CSV: "
                                                        "time,event,direction (rising/falling)")
    p.add_argument("--codegen", choices=["c", "vm"],
                   help="the code the model's functions run on: c (compiled with gcc before the first "
                        "run, kept in the cache) or vm (CasADi's virtual machine); default: c where a C "
                        "compiler is present ($DYADC_CODEGEN may say otherwise)")
    p.add_argument("--integrator", choices=["casadi", "native"],
                   help="native: the IDAS driver built by `make install` (needs the model in C; "
                        "otherwise CasADi's, with a warning), or casadi: IDAS through CasADi; default: "
                        "native where it can run the model ($DYADC_INTEGRATOR may say otherwise)")
    p.add_argument("--no-cache", action="store_true",
                   help="compile from source and store nothing (docs/cache.md; or DYADC_CACHE_DIR=off)")
    p.add_argument("--keep-partial", action="store_true",
                   help="when the run fails, write what it reached to FILE.partial.EXT (with --output)")
    p.add_argument("--strict-bounds", action="store_true",
                   help="stop the run where a variable leaves its declared min/max (default: a "
                        "warning, and the run goes on)")
    p.add_argument("--max-output-values", type=int, metavar="N",
                   help="refuse runs storing more than N output values (times x signals; default "
                        "$DYADC_MAX_OUTPUT_VALUES or 10000000)")
    p.set_defaults(run=run_simulate)


ADDERS = {"simulate": add_simulate}


# ----------------------------------------------------------------------------------------- commands

def run_simulate(args) -> int:
    from compiler.cli import options
    from compiler.api import simulate_compiled
    from compiler.cli.outputs import check_simulate_outputs, listed, write_result
    from compiler.pipeline import compile_or_load
    # Every option is checked before the compiler runs: a typo must cost neither a compile nor a run.
    options.check_span(args.start, args.stop)
    options.check_positive("--rtol", args.rtol)
    options.check_positive("--atol", args.atol)
    limit = options.max_output_values(args.max_output_values)
    saveat = None if args.saveat is None else options.parse_saveat(args.saveat, args.start, args.stop)
    times = args.points if saveat is None else saveat.count()
    if saveat is None:
        options.check_points(args.points)
    options.check_output_size(times, 0, limit, f"--saveat {args.saveat}" if saveat else f"--points {times}")
    overrides = [options.parse_override(text) for text in args.params]
    check_simulate_outputs(args.output, args.plot, args.events)
    from compiler.cache.native import temporary_folder      # --no-cache: C kept nowhere
    compilation = compile_or_load(args.model, args.lib, cache=not args.no_cache, for_runs=True,
                                  codegen=args.codegen, c_folder=temporary_folder() if args.no_cache else None)
    model = compilation.model
    options.check_output_size(times, len(model.output_names), limit, f"{times:,} output times of {model.name}")
    units = model.metadata.get("units", {})
    params = options.convert_overrides(overrides, model.parameters, units)
    names = options.chosen_signals(args.vars, model.output_names)     # names or patterns
    from compiler.pipeline import start_notes    # open connectors; under-determined: what was chosen
    if options.overrides_accepted(model, params):    # once, after every option is checked (else the
        for line in start_notes(compilation):       # run reports the override, with its location)
            print(line, file=sys.stderr)
    try:
        result = simulate_compiled(compilation, args.stop, start=args.start, rtol=args.rtol,
                                   atol=args.atol, points=args.points,
                                   saveat=None if saveat is None else saveat.grid(), params=params,
                                   bounds="error" if args.strict_bounds else "warn",
                                   integrator=args.integrator)
    except SimulationError as failure:
        if args.keep_partial and args.output and failure.partial is not None:
            partial = _partial_path(args.output)
            failure.partial.write(partial, names)
            failure.notes.append(Note(f"the run up to t = {failure.partial.time[-1]:.10g} is in {partial}"))
        raise
    written = write_result(result, names or result.names, units, model.name, args.output, args.plot,
                           args.events)
    stats = result.stats
    events = len(result.events)
    print(f"simulated {compilation.model.name} from {args.start:g} to {args.stop:g} s "
          f"{integrator_named(stats)}: "
          f"{stats.get('steps')} steps, {events} event{'s' if events != 1 else ''}, compile "
          f"{stats.get('compile_time', 0):.2f} s, run {stats.get('run_time', 0):.2f} s "
          f"{code_named(stats)}"
          + (f"; wrote {listed(written)}" if written else ""), file=sys.stderr)
    if not args.output and not args.plot:
        _print_final(result, names)
    return 0


def code_named(stats: dict) -> str:
    """Where the summary line says the run went: "in C", or "on the VM" (and why, not asked)."""
    if stats.get("codegen") == "c":
        return "in C"
    return "on the VM" + (f" ({stats['codegen_why']})" if stats.get("codegen_why") else "")


def integrator_named(stats: dict) -> str:
    """Which IDAS the summary line says ran: "on native IDAS", "on CasADi's IDAS" (and why, where
    the native driver was the first choice), or both where a run's state sets took both."""
    names = {"native": "native IDAS", "casadi": "CasADi's IDAS"}
    ran = " and ".join(names.get(n, n) for n in str(stats.get("integrator", "casadi")).split(", "))
    return f"on {ran}" + (f" ({stats['integrator_why']})" if stats.get("integrator_why") else "")


def _partial_path(output: str) -> str:
    """out/run.csv -> out/run.partial.csv: a failed run's file is never taken for a complete one."""
    stem, extension = os.path.splitext(output)
    return f"{stem}.partial{extension}"


def _print_final(result, names) -> None:
    names = names or result.names
    width = max((len(n) for n in names), default=4)
    print(f"{'time':<{width}}  {result.time[-1]:.10g}")
    for n in names:
        print(f"{n:<{width}}  {result[n][-1]:.10g}")
