"""Before a run (and in `dyadc check`): every parameter the equations use has a value, and no
override (`-p name=VALUE`) names a parameter that is fixed when the model is compiled. The error
for a missing value points at the declaration, with a note where the component is instantiated."""
from __future__ import annotations

from typing import Iterable

from compiler.errors import DyadError, Note
from compiler.model.flat import FlatSystem


def require_tunable_overrides(flat: FlatSystem, overrides=None) -> None:
    """Before a run: an override (`-p name=VALUE`) names no parameter that is fixed when the
    model is compiled (a structural one sizes arrays and picks branches; a constant or `final`
    one is bound by its declaration)."""
    fixed = {p.name: p for p in flat.parameters if not p.tunable}
    for name in overrides or ():
        parameter = fixed.get(name)
        if parameter is None:
            continue
        local = name.rsplit(".", 1)[-1]
        if parameter.variability == "structural":
            raise DyadError(
                f"parameter `{name}` of `{flat.name}` is structural: it is fixed when the model is "
                f"compiled (array sizes, branches), so a run cannot override it", parameter.origin.span,
                hint=f"change it in the source: the value in its declaration, or a modifier where "
                     f"its component is used, e.g. `Name({local} = VALUE)`")
        what = "a constant" if parameter.variability == "constant" else "final"
        raise DyadError(f"parameter `{name}` of `{flat.name}` is {what}: its declaration binds its "
                        f"value, so a run cannot override it", parameter.origin.span,
                        hint="override the parameters its value is computed from, if any")


def require_parameter_values(flat: FlatSystem, used: set[str] | None = None, overrides=None) -> None:
    """Before a run (and in `dyadc check`, which runs without overrides): every parameter the
    equations use (`used`; default: those of `flat`'s equations) has a value, from its declaration,
    a modifier where its component is used, or the caller (`-p name=VALUE`)."""
    given = set(overrides or ())
    used = used_parameter_names(flat) if used is None else used
    missing = [p for p in flat.parameters
               if p.name in used and p.value is None and p.default is None and p.name not in given]
    if missing:
        raise missing_values_error(flat, missing)


def used_parameter_names(flat: FlatSystem) -> set[str]:
    """The parameters `flat`'s equations and initial equations use, closed over the bindings of
    other parameters."""
    return parameter_closure(flat, (s.name for e in flat.equations + flat.initial_equations
                                    for s in e.residual.free_symbols))


def parameter_closure(flat: FlatSystem, names: Iterable[str]) -> set[str]:
    """The parameters among `names`, and every parameter their bindings use, transitively."""
    by_name = {p.name: p for p in flat.parameters}
    pending = [name for name in names if name in by_name]
    used: set[str] = set()
    while pending:
        name = pending.pop()
        if name in used:
            continue
        used.add(name)
        default = by_name[name].default
        if default is not None:
            pending.extend(s.name for s in default.free_symbols if s.name in by_name)
    return used


def missing_values_error(flat: FlatSystem, missing: list) -> DyadError:
    """Parameters without a value, located at the first one's declaration, with a note at the
    place where its component is instantiated (where a value belongs) and a hint in its own type."""
    first = missing[0]
    names = ", ".join(f"`{p.name}`" for p in missing)
    example = " ".join(f"-p {p.name}=VALUE" for p in missing[:3])
    local = first.name.rsplit(".", 1)[-1]
    notes = [Note(f"`{p.name}` is declared here without a value", p.origin.span) for p in missing[1:8]]
    where = f"`parameter {local}::{first.type_name} = VALUE` in the declaration"
    if first.instance_span is not None:
        instance = first.origin.path.rsplit(".", 1)[-1]
        notes.insert(0, Note(f"`{instance}` is instantiated here: give `{local}` a value in its "
                             f"modifiers, e.g. `{local} = VALUE`", first.instance_span))
        where = f"a modifier where `{instance}` is instantiated (`{local} = VALUE`, see the note)"
    return DyadError(
        f"parameter{'s' if len(missing) > 1 else ''} {names} of `{flat.name}` "
        f"{'have' if len(missing) > 1 else 'has'} no value", first.origin.span, notes=notes,
        hint=f"give a value in {where}, or when simulating (`dyadc simulate ... {example}`, or "
             f"params={{'{first.name}': VALUE}} from Python)")
