"""Which code a model's functions run on: compiled C where a C compiler is present, CasADi's SX
virtual machine where none is, or where asked (`--codegen vm`, `codegen="vm"`, DYADC_CODEGEN=vm).
The choice is written into the model's metadata (`codegen`: "c" or "vm", `codegen_why` when the
VM was not asked for), from which a run's `Result.stats["codegen"]` and the command line's summary
line report it.
"""
from __future__ import annotations

import os
import warnings

CODEGEN_VARIABLE = "DYADC_CODEGEN"
CHOICES = ("c", "vm")


def requested(codegen: str | None = None) -> str | None:
    """"c", "vm", or None (C where a compiler is present): `codegen`, else $DYADC_CODEGEN."""
    choice = codegen if codegen is not None else (os.environ.get(CODEGEN_VARIABLE, "").strip().lower() or None)
    if choice is not None and choice not in CHOICES:
        from compiler.lower.ccodegen import CodegenWarning
        warnings.warn(f"{CODEGEN_VARIABLE}={choice!r} is neither 'c' nor 'vm'; C is used where a "
                      f"compiler is present", CodegenWarning, stacklevel=2)
        return None
    return choice


def chosen(model) -> str | None:
    """"c" or "vm" once a model's code was chosen, else None."""
    return model.metadata.get("codegen")


def record_choice(model, codegen: str, why: str | None = None):
    """A copy of `model` whose metadata says it runs on `codegen` ("c" or "vm") and, for the VM, why."""
    metadata = {k: v for k, v in model.metadata.items() if k != "codegen_why"}
    return model.replace(metadata={**metadata, "codegen": codegen, **({"codegen_why": why} if why else {})})
