"""Which code a model's functions run on: compiled C where a C compiler is present, CasADi's SX
virtual machine where none is, or where asked (`--codegen vm`, `codegen="vm"`, DYADC_CODEGEN=vm).
The choice is written into the model's metadata (`codegen`: "c" or "vm", `codegen_why` when the
VM was not asked for; compiler/runtime/model_code.py, which also settles a model that reaches a run
undecided), from which a run's `Result.stats["codegen"]` and the command line's summary line
report it.
"""
from __future__ import annotations

import os
import warnings

from compiler.runtime.model_code import chosen, record_choice  # noqa: F401  (the one rule, in the runtime)

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
