"""Dyad's documentation names the standard library by subpackage (RotationalComponents.Components.
IdealGear, ElectricalComponents.Analog.Basic.Resistor, ...), the published libraries by flat path
(RotationalComponents.IdealGear): every subpackage file of ours is a bare extension of the flat
component of the same name, so both paths compile to the same equations."""
from __future__ import annotations

from pathlib import Path

import pytest

from compiler.model.library import Library
from compiler.syntax import parser

COMPONENTS = Path(__file__).resolve().parents[2] / "components"
PACKAGES = ("ElectricalComponents", "RotationalComponents", "TranslationalComponents")
ALIASES = sorted(p for package in PACKAGES for p in (COMPONENTS / package).rglob("*.dyad")
                 if p.parent != COMPONENTS / package)


def test_every_package_has_its_subpackage_paths():
    folders = {p.parent.relative_to(COMPONENTS).as_posix() for p in ALIASES}
    assert {"RotationalComponents/Components", "RotationalComponents/Sources",
            "RotationalComponents/Sensors", "RotationalComponents/Interfaces",
            "TranslationalComponents/Components", "TranslationalComponents/Sources",
            "TranslationalComponents/Sensors", "TranslationalComponents/Interfaces",
            "ElectricalComponents/Analog/Basic", "ElectricalComponents/Analog/Interfaces",
            "ElectricalComponents/Analog/Sources", "ElectricalComponents/Analog/Sensors"} <= folders


@pytest.mark.parametrize("path", ALIASES, ids=lambda p: p.relative_to(COMPONENTS).as_posix())
def test_a_subpackage_path_is_a_bare_extension_of_a_flat_component(path):
    (definition,) = parser.parse_file(str(path)).definitions
    (base,) = definition.extends
    assert definition.declarations == () and definition.relations == () and definition.name == path.stem
    assert base.type_name.split(".")[-1] == path.stem and base.modifications == ()
    assert Library().find(base.type_name) is not None

