"""`dyadc generate`: regenerate the committed modules in generated/ (compiler/lower/generate.py)."""
from __future__ import annotations


def add_generate(sub) -> None:
    p = sub.add_parser("generate", help="regenerate the committed modules in generated/")
    p.add_argument("-o", "--output-dir", default="generated", metavar="DIR")
    p.set_defaults(run=run_generate)


ADDERS = {"generate": add_generate}


def run_generate(args) -> int:
    from compiler.lower.generate import generate_all
    for path in generate_all(args.output_dir):
        print(f"wrote {path}")
    return 0
