"""`make generate`: the modules committed under generated/, rebuilt from the sources."""
from __future__ import annotations

import keyword
import re
from pathlib import Path

# module name -> model spec; every entry is rebuilt by `dyadc generate` and checked for staleness in CI.
# The names are explicit (not module_name()'s qualified default) so that imports stay short.
GENERATED_MODELS = {
    "excavator": "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator",
}


def generate_all(out_dir: str = "generated") -> list[Path]:
    from compiler.lower.codegen import write_module
    from compiler.pipeline import compile_spec
    paths = []
    for module, spec in GENERATED_MODELS.items():
        paths.append(write_module(compile_spec(spec).model, module, out_dir))
    return paths


def module_name(qualified_name: str) -> str:
    """The default module name of a model: every part of its qualified name in snake_case, joined
    by `__`, so that `A.Excavator` and `B.Excavator` get different modules
    (`MultibodyComponents.PlanarMechanics.examples.excavator.Excavator` ->
    `multibody_components__planar_mechanics__examples__excavator__excavator`). Characters a Python
    name cannot hold become `_`."""
    name = "__".join(_snake(part) for part in qualified_name.split("."))
    name = re.sub(r"[^A-Za-z0-9_]", "_", name)
    if not name or name[0].isdigit() or keyword.iskeyword(name):
        name = "_" + name
    return name


def _snake(name: str) -> str:
    """`PlanarMechanics` -> `planar_mechanics`; a run of capitals stays one word (`DCMotor` -> `dcmotor`)."""
    out = []
    for i, ch in enumerate(name):
        if ch.isupper() and i and not name[i - 1].isupper() and name[i - 1] != "_":
            out.append("_")
        out.append(ch.lower())
    return "".join(out)
