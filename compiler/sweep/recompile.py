"""`--recompile`: sweeps over structural parameters (array sizes, branches).

A structural value is compiled into the model, so each distinct combination of structural values
is one compiled model: the samples are grouped by those values, each group is compiled once here
(on the client) and its compiled model is shipped with its samples. The value enters the model
as a modifier on the top component, exactly as if the user had written `Model(n = 3)`: final
parameters stay final, and a value that breaks the model is that case's compile error.
"""
from __future__ import annotations

from typing import Mapping, Sequence

from compiler.errors import DyadError

Case = tuple[tuple[str, float], ...]          # the structural values of one compiled model


def case_of(params: Mapping[str, float], structural: Sequence[str]) -> Case:
    return tuple((name, float(params[name])) for name in structural)


def describe(case: Case) -> str:
    return ", ".join(f"{name} = {value:g}" for name, value in case)


def compile_case(spec: str, lib_dirs: Sequence[str], case: Case):
    """The Compilation of `spec` with the structural values of `case` set as modifiers."""
    from compiler.model.flatten import Flattener
    from compiler.model.instantiate import BoundMod, instantiate, normalize
    from compiler.model.library import Library
    from compiler.model.model_spec import resolve_model
    from compiler.pipeline import compile_flat
    from compiler.syntax import ast

    library = Library(list(lib_dirs))
    resolved = resolve_model(spec, library)
    # A literal needs no scope to evaluate in (the modifier's value is a number).
    mods = tuple(BoundMod(normalize(ast.Modification(name, ast.Number(_literal(value), None))), None)
                 for name, value in case)
    try:
        flat = Flattener(instantiate(resolved, library, mods)).run()
        return compile_flat(flat)
    except DyadError as err:
        raise DyadError(f"cannot compile {resolved.qualified_name} with {describe(case)}: {err.message}",
                        err.span, notes=err.notes, hint=err.hint) from None
    except (ValueError, OverflowError, MemoryError) as err:
        # e.g. a negative array size, which the compiler does not check yet
        raise DyadError(f"cannot compile {resolved.qualified_name} with {describe(case)}: "
                        f"{type(err).__name__}: {err}", hint="check the swept values") from None


def _literal(value: float) -> int | float:
    """Structural values are mostly sizes: 3.0 is written as the integer 3."""
    return int(value) if float(value).is_integer() else float(value)
