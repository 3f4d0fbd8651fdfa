"""`dyadc test [MODEL] [-L DIR] [--golden DIR] [--accept]`: the golden-trajectory cases of the
components' metadata (compiler/testing/golden.py), one line per case as it finishes."""
from __future__ import annotations

import sys

from compiler.cli.arguments import add_lib_argument, add_units_argument


def add_test(sub) -> None:
    p = sub.add_parser("test", help="run the golden-trajectory test cases of the components' metadata")
    p.add_argument("model", metavar="MODEL", nargs="?", help="only this model (default: every model with tests)")
    add_lib_argument(p)
    p.add_argument("--golden", metavar="DIR", help="folder of the golden CSV files "
                   "(default: tests/golden in the current directory)")
    p.add_argument("--accept", "--update", dest="accept", action="store_true",
                   help="write the golden files from a run at rtol 1e-10, creating missing ones "
                        "(never done without this flag)")
    add_units_argument(p)
    p.set_defaults(run=run_test)


ADDERS = {"test": add_test}


def run_test(args) -> int:
    """0 when every case passed (or every golden was written), 1 otherwise, including when there
    was nothing to test."""
    from compiler.testing.golden import DEFAULT_GOLDEN_DIR, run_tests

    def show(report) -> None:
        print(report.format(verbose=not args.accept), flush=True)

    golden_dir = DEFAULT_GOLDEN_DIR if args.golden is None else args.golden
    reports = run_tests(args.model, args.lib, golden_dir=golden_dir, accept=args.accept, on_report=show)
    if not reports:
        print("no test cases found (metadata {\"Dyad\": {\"tests\": ...}} in the libraries named "
              "with -L or DYADC_PATH, or else in the shipped library)", file=sys.stderr)
        return 1
    failed = [r for r in reports if not r.passed]
    verb = "accepted" if args.accept else "passed"
    print(f"{len(reports) - len(failed)} {verb}, {len(failed)} failed", flush=True)
    return 1 if failed else 0
