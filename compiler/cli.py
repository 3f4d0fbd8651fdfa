"""The `dyadc` command line: its parser, the run of one command and the process's exit. Every
user-facing failure is a DyadError rendered without a traceback. The commands live in
cli_source.py (parse, fmt, check, flatten, inspect, compile, generate), cli_simulate.py (simulate,
cache) and cli_studies.py (sweep, test, animate); only the one being run is imported."""
from __future__ import annotations

import argparse
import os
import sys

from compiler.errors import DyadError

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


COMMANDS = ("parse", "fmt", "check", "flatten", "inspect", "compile", "simulate", "run", "sweep", "test",
            "animate", "cache", "generate")
# The module that defines each command's arguments and runs it (`run`: compiler/analysis/command.py).
COMMAND_MODULES = {"parse": "cli_source", "fmt": "cli_source", "check": "cli_source", "flatten": "cli_source",
                   "inspect": "cli_source", "compile": "cli_source", "generate": "cli_source",
                   "simulate": "cli_simulate", "cache": "cli_simulate",
                   "sweep": "cli_studies", "test": "cli_studies", "animate": "cli_studies"}


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The whole command line, or (`command`) the top level with that one command: the others
    are not needed to read its arguments, and building all of them costs a run 5-6 ms (argparse's
    gettext lookups). Unknown or missing commands and `--help` get them all."""
    import importlib
    parser = argparse.ArgumentParser(prog="dyadc", description=DESCRIPTION, epilog=EXAMPLES,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for name in COMMANDS:
        if command not in (None, name):
            continue
        if name == "run":
            from compiler.analysis.command import add_run_parser     # `dyadc run ANALYSIS`
            from compiler.cli_source import LIB_HELP
            add_run_parser(sub, LIB_HELP)
        else:
            importlib.import_module(f"compiler.{COMMAND_MODULES[name]}").ADDERS[name](sub)
    return parser


# ------------------------------------------------------------------------------------------ helpers

def _warning_line(message, category, filename, lineno, file=None, line=None) -> None:
    """Warnings reach a user of the command line as `warning: ...` lines, not as Python's
    file:line report of where in dyadc they were raised."""
    located = getattr(message, "located", False)      # already `FILE:LINE:COL: warning: ...`
    print(message if located else f"warning: {message}", file=file or sys.stderr)


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
        from compiler.units.mode import units_mode
        with element_limit(getattr(args, "max_elements", None)), units_mode(getattr(args, "units", None)):
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
