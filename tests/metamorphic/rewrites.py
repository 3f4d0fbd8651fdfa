"""Equivalent formulations of one component definition: rewrites of its syntax tree.

Each rewrite takes the component (ast.ComponentDef) and a random.Random and returns a Rewrite
(the new definition, and the renaming of variables it made) or None where it does not apply.
Every rewrite keeps the model's mathematics: the same solution, written differently. They touch
only what the component itself declares and writes; inherited and subcomponent equations stay.
"""
from __future__ import annotations

import dataclasses
import random

from compiler.syntax import ast
from tests.metamorphic.algebra import (inline_parameters, literal_kinds, move_terms, name_literals, one_side,
                                       scale_equations, swap_sides)
from tests.metamorphic.forms import PREFIX, Rewrite, leads_with_minus, printable
from tests.metamorphic.restructure import (extract_subexpression, guess_forms, inline_auxiliaries, rename,
                                           reorder, start_forms)

__all__ = ["INTERFACE_KEEPING", "PREFIX", "REWRITES", "Rewrite", "leads_with_minus", "printable", "rewrite"]

REWRITES = {
    "literal_kinds": literal_kinds, "inline_parameters": inline_parameters, "name_literals": name_literals,
    "swap_sides": swap_sides, "move_terms": move_terms, "one_side": one_side,
    "scale_equations": scale_equations, "extract_subexpression": extract_subexpression,
    "inline_auxiliaries": inline_auxiliaries, "start_forms": start_forms, "guess_forms": guess_forms,
    "reorder": reorder, "rename": rename,
}


# Rewrites that keep a definition's interface: what its users (a parent's modifications and
# references like `capacitor.v`) see stays, so they apply inside a subcomponent's definition too.
# Not: parameters inlined (a parent may modify them), auxiliaries inlined or variables renamed
# (a parent may refer to them).
INTERFACE_KEEPING = tuple(name for name in REWRITES if name not in ("inline_parameters", "inline_auxiliaries", "rename"))


def rewrite(component: ast.ComponentDef, seed: int, count: int = 3,
            allowed: tuple[str, ...] = tuple(REWRITES)) -> tuple[Rewrite, list[str]]:
    """`count` rewrites, each drawn (by `seed`) among the `allowed` ones of REWRITES that apply to
    the result of the one before: the rewritten component, the renaming, the names of the
    rewrites applied (fewer than `count` only where none applies any more)."""
    rng = random.Random(seed)
    applied, renamed = [], {}
    for _ in range(count):
        names = list(allowed)
        rng.shuffle(names)
        for name in names:
            result = REWRITES[name](component, rng)
            if result is not None:
                break
        else:
            break
        component = dataclasses.replace(result.component, relations=tuple(
            printable(r) if isinstance(r, ast.Equation) else r for r in result.component.relations))
        for new, old in result.renamed.items():
            renamed[new] = renamed.pop(old, old)
        applied.append(name)
    return Rewrite(component, renamed), applied
