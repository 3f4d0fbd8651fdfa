"""The default name of a generated Python module (`dyadc compile`), from the model's qualified name."""
from __future__ import annotations

import keyword
import re


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
