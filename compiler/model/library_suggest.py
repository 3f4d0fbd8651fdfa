"""The hints of an unknown definition name: the closest component or type the library knows, or,
for a flat path that more than one subpackage defines, the documented paths to choose from.
Functions of a compiler.model.library.Library (its public reading and lookup methods only)."""
from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Mapping

from compiler.errors import DyadError, Span, closest, suggest_name
from compiler.model.library_path import BASE_PACKAGE
from compiler.syntax import ast

PRIMITIVE_TYPES = ("Real", "Integer", "Boolean", "String")
DEFINITION_KEYWORDS = r"(?:component|connector|type|enum|analysis|struct)"
_COMPONENT_HEADER = re.compile(r"(?<![\w.])component\s+(\w+)")
# Dyad's packages of sampled (discrete-time, clocked) components: dyadc has no clocked semantics
# yet, so a use of one is refused by name rather than reported as an unknown name.
SAMPLED_PACKAGES = ("DiscreteComponents",)
# Dyad's friction elements with stuck and sliding modes (Modelica's), which need a discrete state
# dyadc does not have: refused at their declaration by name, in either spelling.
STICK_SLIP_ELEMENTS = {
    "RotationalComponents": ("BearingFriction", "Brake", "Clutch", "OneWayClutch", "Freewheel",
                             "LossyGear", "Gearbox"),
    "TranslationalComponents": ("SupportFriction", "Brake", "MassWithStopAndFriction"),
}
# Elements whose output depends on the past of their inputs, held between events (Modelica's
# names, which Dyad's library mirrors): a flip-flop's or hysteresis' stored bit, an edge's or a
# timer's instant, a thyristor's latched conduction, an arc's burning. dyadc has no discrete states
# (no `pre`, no `when`), so each is refused at its declaration by name.
MEMORY_ELEMENTS = {
    "BlockComponents": ("Pre", "Edge", "FallingEdge", "Change", "Timer", "RSFlipFlop",
                        "LogicalDelay", "TriggeredTrapezoid", "OnOffController", "Hysteresis",
                        "ZeroCrossing"),
    "ElectricalComponents": ("IdealThyristor", "IdealGTOThyristor", "IdealTriac", "OpenerWithArc",
                             "CloserWithArc", "ControlledOpenerWithArc", "ControlledCloserWithArc"),
}


def suggest_component(library, name: str, package: str, file: ast.File | None) -> str | None:
    """In a component position only components are suggested (never a quantity type such as
    `Resistance`): those of the file, of the files parsed so far, and of the folders where
    `name` would be looked up, qualified as the user wrote `name`."""
    ambiguous = ambiguous_alias_hint(library, name, package, file)
    if ambiguous:
        return ambiguous
    prefix, _, local = name.rpartition(".")
    known: set[str] = set()
    if not prefix:
        for parsed in ([file] if file else []) + library.parsed_files():
            known.update(d.name for d in parsed.definitions if isinstance(d, ast.ComponentDef))
    for candidate in library.candidates(name, package, file):
        for root in library.roots_for(candidate):
            for folder in _alias_folders(library, root, candidate.rpartition(".")[0]):
                try:
                    paths = sorted(folder.glob("*.dyad")) if folder.is_dir() else []
                except OSError:         # a name longer than a file name may be
                    continue
                for path in paths:
                    known.update(_COMPONENT_HEADER.findall(library.source_text(path.resolve())))
    match = closest(local, known)
    return f"did you mean `{prefix + '.' if prefix else ''}{match[0]}`?" if match else None


def _alias_folders(library, root, package: str) -> list:
    """The folder of `package` under `root` and those of its subpackages, which its flat paths
    reach (Library.find_aliased)."""
    nested = library.nested_subpackages(package) if package else []
    return [root.joinpath(*name.split(".")) if name else root for name in [package, *nested]]


def suggest_type(library, name: str, package: str, file: ast.File | None) -> str | None:
    """The closest type name: primitive, of the file, of the files parsed so far, or of `Dyad`."""
    ambiguous = ambiguous_alias_hint(library, name, package, file)
    if ambiguous:
        return ambiguous
    known = set(PRIMITIVE_TYPES)
    if file is not None:
        known.update(d.name for d in file.definitions)
    for parsed in library.parsed_files():
        known.update(d.name for d in parsed.definitions)
    for root in library.roots_for(f"{BASE_PACKAGE}.{name}"):
        std = root / BASE_PACKAGE
        if std.is_dir():
            for path in std.glob("*.dyad"):
                known.update(re.findall(rf"{DEFINITION_KEYWORDS}\s+(\w+)",
                                        library.source_text(path.resolve())))
    return suggest_name(name.rsplit(".", 1)[-1], known)


def ambiguous_alias_hint(library, name: str, package: str, file: ast.File | None) -> str | None:
    """`P.X` that no folder defines and several subpackages of P do (`P.A.X`, `P.B.X`): the
    flat path is then no alias, and the hint lists the paths to choose from."""
    for candidate in library.candidates(name, package, file):
        defined = library.subpackage_definitions(candidate)
        if len(defined) > 1:
            return (f"`{candidate}` is defined in more than one subpackage of "
                    f"`{candidate.rpartition('.')[0]}`; name one: "
                    + ", ".join(f"`{found.qualified_name}`" for found in defined))
    return None


@dataclass(frozen=True)
class Refusal:
    """A family of Dyad library components that needs a feature dyadc lacks, refused by name with
    "`P.X` is {what} of Dyad's `P`{why}" and `hint`. `elements`: package -> the refused element
    names, or None for every component of the package."""
    elements: Mapping[str, tuple[str, ...] | None]
    what: str
    why: str
    hint: str

    def refuses(self, package: str, element: str) -> bool:
        if package not in self.elements:
            return False
        names = self.elements[package]
        return names is None or element in names


REFUSALS = (
    Refusal({package: None for package in SAMPLED_PACKAGES}, "a sampled (discrete-time) component",
            "; dyadc does not simulate clocked (sampled) components yet",
            "model the controller or filter in continuous time (BlockComponents.Continuous)"),
    Refusal(STICK_SLIP_ELEMENTS, "a Coulomb friction element",
            ": it switches between stuck and sliding, a discrete mode that dyadc cannot hold yet "
            "(no discrete states)",
            "model the friction as a smooth law of the slip speed (a Damper, or your own component "
            "with tanh(w / w_small))"),
    Refusal(MEMORY_ELEMENTS, "an element with memory",
            ": its output keeps a value set at an earlier event (a latched state), and dyadc has no "
            "discrete states yet (no `pre`, no `when`)",
            "use an element that reads only the present inputs (a threshold comparison, "
            "LogicalSwitch, Switch, IdealOpeningSwitch, IdealDiode)"),
)


def unsupported_component_error(name: str, span: Span | None) -> DyadError | None:
    """The refusal (REFUSALS) of a component of Dyad's standard library that needs a feature dyadc
    lacks (a sampled package's clocked semantics, a friction element's stuck/sliding mode, an
    element's memory), or None."""
    if "." not in name:
        return None
    package, element = name.split(".", 1)[0], name.rsplit(".", 1)[1]
    for refusal in REFUSALS:
        if refusal.refuses(package, element):
            return DyadError(f"`{name}` is {refusal.what} of Dyad's `{package}`{refusal.why}", span,
                             hint=refusal.hint)
    return None
