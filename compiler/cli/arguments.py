"""The arguments several `dyadc` commands share: MODEL, the library folders, the element limit,
the units check's mode, the parameter values."""
from __future__ import annotations

import argparse

LIB_HELP = ("library folder, searched after the shipped library and before $DYADC_PATH "
            "(repeatable); its dyad_functions.py files may run")


def add_lib_argument(p: argparse.ArgumentParser) -> None:
    p.add_argument("-L", "--lib", dest="lib", action="append", default=[], metavar="DIR", help=LIB_HELP)


def add_model_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("model", metavar="MODEL", help="model file, file:Name, or qualified name")
    add_lib_argument(p)
    p.add_argument("--max-elements", type=int, metavar="N",
                   help="refuse array sizes, ranges, loops and component arrays of more than N elements "
                        "(default $DYADC_MAX_ELEMENTS or 1000000)")
    add_units_argument(p)


def add_units_argument(p: argparse.ArgumentParser) -> None:
    from compiler.units import mode
    p.add_argument("--units", choices=mode.MODES, default=None, help=mode.HELP)


def add_params_argument(p: argparse.ArgumentParser, help: str) -> None:
    """`-p NAME=VALUE[UNIT]` (repeatable) into `args.params`; `help` says what the value sets."""
    p.add_argument("-p", dest="params", action="append", default=[], metavar="NAME=VALUE[UNIT]", help=help)
