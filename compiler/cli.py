"""The `dyadc` command line. Every user-facing failure is a DyadError rendered without a traceback."""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from compiler.errors import DyadError, Note, SimulationError

DESCRIPTION = """\
dyadc compiles acausal models written in a Dyad-like language into CasADi functions and
simulates them with SUNDIALS IDAS.

A MODEL is `path/File.dyad` (the component named like the file), `path/File.dyad:Name`,
or a qualified name on the library path (the shipped library, -L DIR, $DYADC_PATH), e.g.
MultibodyComponents.PlanarMechanics.examples.excavator.Excavator.
"""

EXAMPLES = """\
examples:
  dyadc check components
  dyadc simulate MultibodyComponents.PlanarMechanics.examples.excavator.Excavator --stop 12 --output out/excavator.csv
  dyadc simulate tests/models/ComponentTests/Pendulum.dyad --stop 5 --plot pendulum.png
  dyadc inspect MultibodyComponents.PlanarMechanics.examples.excavator.Excavator
"""


LIB_HELP = ("library folder, searched after the shipped library and before $DYADC_PATH "
            "(repeatable); its dyad_functions.py files may run")


def _add_model(p: argparse.ArgumentParser) -> None:
    p.add_argument("model", metavar="MODEL", help="model file, file:Name, or qualified name")
    p.add_argument("-L", "--lib", dest="lib", action="append", default=[], metavar="DIR", help=LIB_HELP)
    p.add_argument("--max-elements", type=int, metavar="N",
                   help="refuse array sizes, ranges, loops and component arrays of more than N elements "
                        "(default $DYADC_MAX_ELEMENTS or 1000000)")


COMMANDS = ("parse", "fmt", "check", "flatten", "inspect", "compile", "simulate", "run", "sweep", "test",
            "animate", "cache", "generate")


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The whole command line, or (`command`) the top level with that one command: the others
    are not needed to read its arguments, and building all of them costs a run 5-6 ms (argparse's
    gettext lookups). Unknown or missing commands and `--help` get them all."""
    parser = argparse.ArgumentParser(prog="dyadc", description=DESCRIPTION, epilog=EXAMPLES,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True

    if command in (None, "parse"):
        p = sub.add_parser("parse", help="parse a .dyad file and print its definitions")
        p.add_argument("file", metavar="FILE")
        p.set_defaults(run=_cmd_parse)

    if command in (None, "fmt"):
        p = sub.add_parser("fmt", help="reprint a .dyad file in canonical form")
        p.add_argument("file", metavar="FILE")
        p.add_argument("--write", "-w", action="store_true", help="rewrite the file in place")
        p.set_defaults(run=_cmd_fmt)

    if command in (None, "check"):
        p = sub.add_parser("check", help="flatten a model (or every model under a directory) and check balance")
        _add_model(p)
        p.set_defaults(run=_cmd_check)

    if command in (None, "flatten"):
        p = sub.add_parser("flatten", help="print the flat equations with their origins")
        _add_model(p)
        p.set_defaults(run=_cmd_flatten)

    if command in (None, "inspect"):
        p = sub.add_parser("inspect", help="print every pass of the structural analysis")
        _add_model(p)
        p.add_argument("--stop", type=float, metavar="T",
                       help="also simulate to T and list the state-set switches and events of the run")
        p.add_argument("--rtol", type=float, default=1e-6, help="relative tolerance of that run (default 1e-6)")
        p.set_defaults(run=_cmd_inspect)

    if command in (None, "compile"):
        p = sub.add_parser("compile", help="write a Python module for a model")
        _add_model(p)
        p.add_argument("-o", "--output-dir", default="generated", metavar="DIR")
        p.add_argument("--name", help="module name (default: the qualified model name in snake_case, "
                                      "packages joined by `__`, e.g. component_tests__pendulum)")
        p.add_argument("--standalone", action="store_true",
                       help="copy the runtime package beside the module (then it needs only casadi and numpy)")
        p.set_defaults(run=_cmd_compile)

    if command in (None, "simulate"):
        p = sub.add_parser("simulate", help="compile and simulate a model")
        _add_model(p)
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
        p.add_argument("-p", dest="params", action="append", default=[], metavar="NAME=VALUE[UNIT]",
                       help="override a parameter by dotted path, optionally with a unit converted to the "
                            "declared one, e.g. -p L=100mm (repeatable)")
        p.add_argument("--vars", nargs="+", metavar="NAME", help="signals to write (default: all)")
        p.add_argument("--output", metavar="FILE",
                       help="write the result; the extension picks the format: .csv, .parquet, .mat, .npz")
        p.add_argument("--plot", metavar="FILE.png", help="plot the result, one subplot per unit "
                                                          "(.png, .pdf, .svg, ...)")
        p.add_argument("--codegen", choices=["c"], help="compile the model to C with gcc (the first run "
                                                        "builds it in the background, later runs use it)")
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
        p.set_defaults(run=_cmd_simulate)

    if command in (None, "run"):
        from compiler.analysis.command import add_run_parser     # `dyadc run ANALYSIS`
        add_run_parser(sub, LIB_HELP)

    if command in (None, "sweep"):
        p = sub.add_parser("sweep", help="run a model over a grid or random samples of its parameters "
                                         "(Dask or --serial); see docs/sweeps.md")
        _add_model(p)
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
        p.set_defaults(run=_cmd_sweep)

    if command in (None, "test"):
        p = sub.add_parser("test", help="run the golden-trajectory test cases of the components' metadata")
        p.add_argument("model", metavar="MODEL", nargs="?", help="only this model (default: every model with tests)")
        p.add_argument("-L", "--lib", dest="lib", action="append", default=[], metavar="DIR", help=LIB_HELP)
        p.add_argument("--golden", metavar="DIR", help="folder of the golden CSV files "
                       "(default: tests/golden in the current directory)")
        p.add_argument("--accept", "--update", dest="accept", action="store_true",
                       help="write the golden files from a run at rtol 1e-10, creating missing ones "
                            "(never done without this flag)")
        p.set_defaults(run=_cmd_test)

    if command in (None, "animate"):
        p = sub.add_parser("animate", help="simulate a planar model and write a side-view GIF or MP4")
        _add_model(p)
        p.add_argument("--stop", type=float, required=True, metavar="T", help="simulated time span [0, T]")
        p.add_argument("--output", metavar="FILE", help="default: <Model>.gif (or .mp4 with --format mp4)")
        p.add_argument("--format", choices=["gif", "mp4"], help="default: from --output's extension, else gif; "
                                                                "mp4 needs ffmpeg on PATH")
        p.add_argument("--fps", type=int, default=12, metavar="N", help="frames per second (default 12)")
        length = p.add_mutually_exclusive_group()
        length.add_argument("--frames", type=int, metavar="N", help="number of frames (default 120)")
        length.add_argument("--duration", type=float, metavar="SECONDS",
                            help="length of the animation; frames = duration x fps")
        p.set_defaults(run=_cmd_animate)

    if command in (None, "cache"):
        p = sub.add_parser("cache", help="where the compilation cache is and what it holds; clear it")
        p.add_argument("action", choices=["info", "clear"])
        p.set_defaults(run=_cmd_cache)

    if command in (None, "generate"):
        p = sub.add_parser("generate", help="regenerate the committed modules in generated/")
        p.add_argument("-o", "--output-dir", default="generated", metavar="DIR")
        p.set_defaults(run=_cmd_generate)
    return parser


# ----------------------------------------------------------------------------------------- commands

def _cmd_parse(args) -> int:
    from compiler.syntax.parser import parse_file, summarize
    print(summarize(parse_file(args.file)))
    return 0


def _cmd_fmt(args) -> int:
    from compiler.syntax.format import format_file
    from compiler.syntax.parser import parse_file
    text = format_file(parse_file(args.file))
    if args.write:
        Path(args.file).write_text(text, encoding="utf-8")
    else:
        sys.stdout.write(text)
    return 0


def _cmd_check(args) -> int:
    from compiler.model.flatten import check_library, flatten_model, summarize
    from compiler.model.model_check import assess
    if os.path.isdir(args.model):
        problems = check_library(args.model)
        for line in problems:
            print(line)
        return 1 if any("error" in line for line in problems) else 0
    flat = flatten_model(args.model, args.lib)
    verdict = assess(flat)           # the same checks as `simulate` runs before compiling
    print(summarize(flat, verdict))
    return 0


def _cmd_flatten(args) -> int:
    from compiler.model.flatten import flatten_model, format_flat
    print(format_flat(flatten_model(args.model, args.lib)))
    return 0


def _cmd_inspect(args) -> int:
    from compiler.inspect_report import format_report, format_switch_log
    from compiler.pipeline import compile_spec
    compilation = compile_spec(args.model, args.lib)
    print(format_report(compilation))
    if args.stop is not None:
        from compiler import api
        from compiler.runtime.options import SimulationOptions
        SimulationOptions(stop=args.stop, rtol=args.rtol, atol=args.rtol).validated()   # clear errors first
        print()
        print(format_switch_log(api.simulate_compiled(compilation, args.stop, rtol=args.rtol,
                                                      atol=args.rtol, progress=False)))
    return 0


def _cmd_compile(args) -> int:
    from compiler.cli_outputs import check_output_folder
    from compiler.lower.codegen import write_module
    from compiler.lower.generate import module_name
    from compiler.pipeline import compile_spec
    check_output_folder(args.output_dir, "-o")      # before the compile it would otherwise waste
    compilation = compile_spec(args.model, args.lib)
    name = args.name or module_name(compilation.model.name)
    path = write_module(compilation.model, name, args.output_dir, standalone=args.standalone)
    print(f"wrote {path}")
    return 0


def _cmd_simulate(args) -> int:
    background: list = []         # a C library being built while the run goes on
    try:
        return _simulate(args, background)
    finally:
        for build in background:
            print(build.finish(), file=sys.stderr)


def _simulate(args, background: list) -> int:
    from compiler import cli_options as options
    from compiler.api import simulate_compiled
    from compiler.cli_outputs import check_simulate_outputs, write_result
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
    check_simulate_outputs(args.output, args.plot)
    compilation = compile_or_load(args.model, args.lib, cache=not args.no_cache)
    from compiler.pipeline import start_notes    # under-determined: what was chosen
    for note in start_notes(compilation):
        print(f"note: {note}", file=sys.stderr)
    model = compilation.model
    options.check_output_size(times, len(model.output_names), limit, f"{times:,} output times of {model.name}")
    units = model.metadata.get("units", {})
    params = options.convert_overrides(overrides, model.parameters, units)
    if args.codegen == "c":
        import time
        from compiler.cache.native import use_c_code
        began = time.perf_counter()
        background += filter(None, [use_c_code(compilation, cache=not args.no_cache)])
        compilation.timings["codegen c"] = time.perf_counter() - began
    try:
        result = simulate_compiled(compilation, args.stop, start=args.start, rtol=args.rtol,
                                   atol=args.atol, points=args.points,
                                   saveat=None if saveat is None else saveat.grid(), params=params,
                                   bounds="error" if args.strict_bounds else "warn")
    except SimulationError as failure:
        if args.keep_partial and args.output and failure.partial is not None:
            partial = _partial_path(args.output)
            failure.partial.write(partial, args.vars or None)
            failure.notes.append(Note(f"the run up to t = {failure.partial.time[-1]:.10g} is in {partial}"))
        raise
    names = args.vars or None
    if names:
        for n in names:
            result[n]           # unknown names fail before anything is written
    write_result(result, names or result.names, units, model.name, args.output, args.plot)
    stats = result.stats
    print(f"simulated {compilation.model.name} from {args.start:g} to {args.stop:g} s: "
          f"{stats.get('steps')} steps, compile {stats.get('compile_time', 0):.2f} s, "
          f"run {stats.get('run_time', 0):.2f} s", file=sys.stderr)
    if not args.output and not args.plot:
        _print_final(result, names)
    return 0


def _cmd_sweep(args) -> int:
    from compiler.sweep.command import main_sweep
    return main_sweep(args)


def _cmd_test(args) -> int:
    from compiler.testing.golden import main_test
    return main_test(args.model, args.lib, golden_dir=args.golden, accept=args.accept)


def _cmd_animate(args) -> int:
    from compiler.render.animate import main_animate
    return main_animate(args.model, args.lib, args.stop, args.output, fps=args.fps, frames=args.frames,
                        duration=args.duration, video_format=args.format)


def _cmd_cache(args) -> int:
    from compiler.cache.command import main_cache
    return main_cache(args.action)


def _cmd_generate(args) -> int:
    from compiler.lower.generate import generate_all
    for path in generate_all(args.output_dir):
        print(f"wrote {path}")
    return 0


# ------------------------------------------------------------------------------------------ helpers

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


def _warning_line(message, category, filename, lineno, file=None, line=None) -> None:
    """Warnings reach a user of the command line as `warning: ...` lines, not as Python's
    file:line report of where in dyadc they were raised."""
    print(f"warning: {message}", file=file or sys.stderr)


# The variables OpenBLAS reads for its thread count (the first one set wins).
BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS")


def blas_on_one_thread() -> None:
    """Load numpy's OpenBLAS with one thread unless the user chose a count. Its worker threads
    (one per core) cost a cached `dyadc simulate` 50-100 ms of CPU time at start, on a machine that
    is busy anyway; dyadc's matrices are small (CasADi and IDAS solve the large systems), and a
    sweep runs one process per core. OpenBLAS reads the variable when it is loaded, so this only
    acts before numpy is imported (not for a command line called from a Python process that
    already imported it). Results are the same: one thread or several, these small products and
    factorizations are computed alike (the excavator's and pendulum's outputs compared byte for
    byte)."""
    if "numpy" not in sys.modules and not any(name in os.environ for name in BLAS_THREAD_VARIABLES):
        os.environ["OPENBLAS_NUM_THREADS"] = "1"


def main(argv: list[str] | None = None) -> int:
    """Run the command line `argv` (default: this program's arguments) and give its exit status.
    Called as the program itself (no `argv`), it ends the process when the command is done."""
    status = run_command(argv)
    if argv is None:
        exit_without_teardown(status)
    return status


def exit_without_teardown(status: int) -> None:
    """End this process with `status` once its output is written and its atexit handlers ran
    (temporary folders, log handlers, child processes), without Python's teardown: freeing the
    compiler's sympy expressions object by object and clearing every module cost a compiling run
    0.18-0.21 s of CPU after its work was done (0.02-0.03 s from the cache). Nothing is lost:
    dyadc closes every file it writes; the process ends normally instead when a thread besides
    the main one is still running (its work would be cut short) or the output cannot be flushed
    (a closed pipe: Python's own exit reports it)."""
    import atexit
    import threading
    run_exit_handlers = getattr(atexit, "_run_exitfuncs", None)
    if run_exit_handlers is None or threading.active_count() != 1:
        return
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except (OSError, ValueError):
        return
    run_exit_handlers()
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except (OSError, ValueError):
        pass
    os._exit(status)


def run_command(argv: list[str] | None = None) -> int:
    blas_on_one_thread()
    arguments = sys.argv[1:] if argv is None else list(argv)
    command = arguments[0] if arguments and arguments[0] in COMMANDS else None
    args = build_parser(command).parse_args(arguments)
    import warnings
    warnings.showwarning = _warning_line
    try:
        from compiler import cli_options
        from compiler.model.size_limits import element_limit
        cli_options.check_arguments(arguments)
        cli_options.check_paths(args)
        with element_limit(getattr(args, "max_elements", None)):
            return args.run(args) or 0
    except DyadError as err:
        print(err.format(), file=sys.stderr)
        return 1
    except KeyboardInterrupt as err:             # a run says where: "interrupted at t = ..."
        print(str(err) or "interrupted", file=sys.stderr)
        return 130
    except Exception as err:          # a bug of ours: say so briefly, the traceback only on request
        if os.environ.get("DYADC_DEBUG"):
            raise
        from compiler.runtime import ModelInputError, SimulationFailed
        if isinstance(err, (ModelInputError, SimulationFailed)):
            print(f"error: {err}", file=sys.stderr)
            return 1
        print(f"internal error: {type(err).__name__}: {err}\n"
              "this is a bug in dyadc; rerun with DYADC_DEBUG=1 for the traceback", file=sys.stderr)
        return 2
