"""`make generate`: the modules committed under generated/, rebuilt from the sources."""
from __future__ import annotations

from pathlib import Path

# module name -> model spec; every entry is rebuilt by `dyadc generate` and checked for staleness in CI
GENERATED_MODELS = {
    "excavator": "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator",
}


def generate_all(out_dir: str = "generated") -> list[Path]:
    from compiler.codegen import write_module
    from compiler.pipeline import compile_spec
    paths = []
    for module, spec in GENERATED_MODELS.items():
        paths.append(write_module(compile_spec(spec).model, module, out_dir))
    return paths
