"""The `dyadc` command line. Every user-facing failure is a DyadError rendered without a traceback."""
from __future__ import annotations

import argparse
import sys

from compiler.errors import DyadError


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="dyadc",
        description="dyadc compiles Dyad-like acausal models to CasADi and simulates them with IDAS.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.run(args) or 0
    except DyadError as err:
        print(err.format(), file=sys.stderr)
        return 1
