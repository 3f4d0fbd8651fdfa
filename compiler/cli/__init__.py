"""The `dyadc` command line: its parser, the run of one command and the process's exit status.

Each command family is one module of this package (FAMILIES); only the module of the command being
run is imported. Every user-facing failure is a DyadError rendered without a traceback. The stage
packages print nothing: the commands here print what they return and the notes they pass on.
"""
from __future__ import annotations

import argparse
import importlib
import os
import sys

from compiler.cli.process import (BLAS_THREAD_VARIABLES, blas_on_one_thread, exit_without_teardown,
                                  quiet_closed_pipe, warning_line)
from compiler.errors import DyadError

__all__ = ["BLAS_THREAD_VARIABLES", "COMMANDS", "FAMILIES", "blas_on_one_thread", "build_parser",
           "exit_without_teardown", "main", "run_command"]

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

# The command families: a module of compiler/cli/ and the commands it defines, in the order
# `dyadc --help` lists them. The module has `ADDERS = {command: add(subparsers)}`; each adder sets
# the parser's `run` default to the function that runs the command (docs/cli.md, "Adding a command").
FAMILIES = (
    ("source", ("parse", "fmt", "check", "flatten", "inspect", "compile")),
    ("simulate", ("simulate",)),
    ("run", ("run",)),
    ("sweep", ("sweep",)),
    ("golden", ("test",)),
    ("animate", ("animate",)),
    ("cache", ("cache",)),
    ("generate", ("generate",)),
    ("linear", ("linearize",)),
    ("fmu", ("fmu",)),
)
COMMANDS = tuple(command for _, commands in FAMILIES for command in commands)


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The whole command line, or (`command`) the top level with that one command: the others
    are not needed to read its arguments and cost a run milliseconds to build. Unknown or missing
    commands and `--help` get them all."""
    parser = argparse.ArgumentParser(prog="dyadc", description=DESCRIPTION, epilog=EXAMPLES,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    from compiler import __version__
    parser.add_argument("--version", action="version", version=f"dyadc {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for family, commands in FAMILIES:
        for name in commands:
            if command in (None, name):
                importlib.import_module(f"compiler.cli.{family}").ADDERS[name](sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line `argv` (default: this program's arguments) and give its exit status.
    Called as the program itself (no `argv`), it ends the process when the command is done."""
    status = run_command(argv)
    if argv is None:
        exit_without_teardown(status)
    return status


def run_command(argv: list[str] | None = None) -> int:
    blas_on_one_thread()
    arguments = sys.argv[1:] if argv is None else list(argv)
    command = arguments[0] if arguments and arguments[0] in COMMANDS else None
    args = build_parser(command).parse_args(arguments)
    import warnings
    warnings.showwarning = warning_line
    try:
        from compiler.cli import options
        from compiler.model.size_limits import element_limit
        options.check_arguments(arguments)
        options.check_paths(args)
        from compiler.units.mode import units_mode
        with element_limit(getattr(args, "max_elements", None)), units_mode(getattr(args, "units", None)):
            return args.run(args) or 0
    except DyadError as err:
        print(err.format(), file=sys.stderr)
        return 1
    except BrokenPipeError:                      # `dyadc inspect M | head`: the reader is gone
        return quiet_closed_pipe()
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
