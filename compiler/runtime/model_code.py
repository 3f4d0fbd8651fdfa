"""The code a model's functions run on, settled before its first run whoever runs it (`dyadc
simulate`, a generated module, a model read back with `CompiledModel.from_dict`, a model lowered
without C): compiled C where a C compiler is present, CasADi's SX virtual machine where none is or
where asked; written into the model's metadata (`codegen` "c" or "vm", `codegen_why` when the VM
was not asked for) and reported by every run (`Result.stats["codegen"]`, `["codegen_why"]`).

The runtime imports nothing of the compiler, so it does not build C itself: a model that reaches
a run undecided is handed to the build that dyadc's installation declares under the entry point
group ENTRY_POINT_GROUP (pyproject.toml: compiler/cache/c_code.py's `for_a_run`, the same build
and content-keyed cache `dyadc simulate` uses), once per model object. A standalone module's copy
of the runtime (`dyadc compile --standalone`, which promises only casadi and numpy) never looks
one up: it runs on the C library written beside it, else on the VM, and says so.
"""
from __future__ import annotations

import threading
from typing import Callable

from .model import CompiledModel

ENTRY_POINT_GROUP = "dyadc.model_code"
ENTRY_POINT_NAME = "build"
CODEGEN, CODEGEN_WHY = "codegen", "codegen_why"
# the runtime of the installed compiler, not a standalone module's copy (package dyad_runtime)
INSTALLED_RUNTIME = "compiler.runtime"
STANDALONE_WHY = ("a standalone module's runtime builds no C code (dyadc compile --standalone needs "
                  "only casadi and numpy); regenerate the module where a C compiler is present to "
                  "write its C library beside it")
# why such state sets are not built during the run (the first run's cost), with the measurements:
# docs/numerics.md, "Compiled code before every first run, and state sets made at run time"
RUN_TIME_STATE_SET_WHY = ("a state set made at run time has no C library: gcc would add about 0.4 s "
                          "per state set to the run")
_BUILT = "model code for a run"
_lock = threading.Lock()
_found: dict[str, tuple] = {}


def chosen(model: CompiledModel) -> str | None:
    """"c" or "vm" once a model's code was chosen, else None."""
    return model.metadata.get(CODEGEN)


def record_choice(model: CompiledModel, codegen: str, why: str | None = None) -> CompiledModel:
    """A copy of `model` whose metadata says it runs on `codegen` ("c" or "vm") and, for the VM, why."""
    metadata = {k: v for k, v in model.metadata.items() if k != CODEGEN_WHY}
    return model.replace(metadata={**metadata, CODEGEN: codegen, **({CODEGEN_WHY: why} if why else {})})


def needs_code(model: CompiledModel) -> bool:
    """Whether `model` reaches a run with its code unsettled: no choice made, or C chosen and its
    library not with it (a model serialized and read back). A model put on the VM (asked for, or
    where no compiler was) stays there."""
    return model.native_library is None and chosen(model) != "vm"


def code_builder(package: str = __package__) -> tuple[Callable | None, str | None]:
    """(the build declared by dyadc's installation, None), or (None, why there is none); looked
    up once per process. `package`: the runtime's own package name."""
    if package != INSTALLED_RUNTIME:
        return None, STANDALONE_WHY
    with _lock:
        if "builder" not in _found:
            _found["builder"] = _look_up()
        return _found["builder"]


def _look_up() -> tuple[Callable | None, str | None]:
    from importlib.metadata import entry_points
    found = [e for e in entry_points(group=ENTRY_POINT_GROUP) if e.name == ENTRY_POINT_NAME]
    if not found:
        return None, (f"dyadc's installation declares no C build (entry point group "
                      f"{ENTRY_POINT_GROUP!r}; `pip install -e .` or `make install` declares it)")
    try:
        return found[0].load(), None
    except (ImportError, AttributeError) as err:
        return None, f"the C build declared by dyadc's installation does not load ({err})"


def on_its_code(model: CompiledModel, package: str = __package__) -> CompiledModel:
    """`model` on the code its runs take: itself when settled (needs_code), else built once per
    model object by the installation's C build (C, or the VM with why), or on the VM with why
    where there is no build to call."""
    if not needs_code(model):
        return model

    def settle() -> CompiledModel:
        build, why = code_builder(package)
        return build(model) if build is not None else record_choice(model, "vm", why)
    return model.derived(_BUILT, settle)


def made_at_run_time(state_set: CompiledModel, first: CompiledModel) -> CompiledModel:
    """A state set made during a run (universal.py) settled on the VM, never built then
    (RUN_TIME_STATE_SET_WHY): with the VM reason of the run's first state set where that one is on
    the VM too."""
    if first.native_library is None:
        return record_choice(state_set, "vm", first.metadata.get(CODEGEN_WHY))
    return record_choice(state_set, "vm", RUN_TIME_STATE_SET_WHY)


def code_stats(model: CompiledModel) -> dict:
    """What a run reports of its model's code: {"codegen": "c" | "vm"} and, where the VM was not
    asked for, "codegen_why"."""
    stats = {"codegen": "c" if model.native_library is not None else "vm"}
    if stats["codegen"] == "vm" and model.metadata.get(CODEGEN_WHY):
        stats["codegen_why"] = model.metadata[CODEGEN_WHY]
    return stats
