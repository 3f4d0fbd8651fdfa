"""`dyadc generate` (`make generate`): the modules committed under generated/, rebuilt from the
sources."""
from __future__ import annotations

from pathlib import Path

# module name -> model spec; every entry is rebuilt by `dyadc generate` and checked for staleness in CI.
# The names are explicit (not module_name()'s qualified default) so that imports stay short.
GENERATED_MODELS = {
    "excavator": "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator",
}


def add_generate(sub) -> None:
    p = sub.add_parser("generate", help="regenerate the committed modules in generated/")
    p.add_argument("-o", "--output-dir", default="generated", metavar="DIR")
    p.set_defaults(run=run_generate)


ADDERS = {"generate": add_generate}


def run_generate(args) -> int:
    for path in generate_all(args.output_dir):
        print(f"wrote {path}")
    return 0


def generate_all(out_dir: str = "generated") -> list[Path]:
    from compiler.lower.codegen import write_module
    from compiler.pipeline import compile_spec
    return [write_module(compile_spec(spec).model, module, out_dir) for module, spec in GENERATED_MODELS.items()]
