"""One alias rule for the standard library's two spellings: Dyad's documentation names a component
by subpackage (RotationalComponents.Components.IdealGear, ElectricalComponents.Analog.Basic.
Resistor), the published libraries by the flat path (RotationalComponents.IdealGear). The library
holds each component once, at its documented path; the flat path resolves to it through
Library.find_aliased (compiler/model/library.py), and no file re-declares a component of its own
package under the other spelling."""
from __future__ import annotations

from pathlib import Path

import pytest

from compiler.errors import DyadError
from compiler.model.flatten import flatten_model
from compiler.model.library import Library
from compiler.model.parameter_checks import require_parameter_values
from compiler.syntax import ast, parser

COMPONENTS = Path(__file__).resolve().parents[2] / "components"
STANDARD_PACKAGES = ("ElectricalComponents", "RotationalComponents", "TranslationalComponents",
                     "ThermalComponents", "BlockComponents", "HydraulicComponents")

# one representative of every package and subpackage: (flat path, documented path)
SPELLINGS = [
    ("ElectricalComponents.Resistor", "ElectricalComponents.Analog.Basic.Resistor"),
    ("ElectricalComponents.OnePort", "ElectricalComponents.Analog.Interfaces.OnePort"),
    ("ElectricalComponents.SineVoltage", "ElectricalComponents.Analog.Sources.SineVoltage"),
    ("ElectricalComponents.CurrentSensor", "ElectricalComponents.Analog.Sensors.CurrentSensor"),
    ("ElectricalComponents.IdealDiode", "ElectricalComponents.Analog.Ideal.IdealDiode"),
    ("RotationalComponents.Inertia", "RotationalComponents.Components.Inertia"),
    ("RotationalComponents.PartialTwoSplines", "RotationalComponents.Interfaces.PartialTwoSplines"),
    ("RotationalComponents.TorqueSource", "RotationalComponents.Sources.TorqueSource"),
    ("RotationalComponents.SpeedSensor", "RotationalComponents.Sensors.SpeedSensor"),
    ("TranslationalComponents.Mass", "TranslationalComponents.Components.Mass"),
    ("TranslationalComponents.PartialRigid", "TranslationalComponents.Interfaces.PartialRigid"),
    ("TranslationalComponents.Position", "TranslationalComponents.Sources.Position"),
    ("TranslationalComponents.ForceSensor", "TranslationalComponents.Sensors.ForceSensor"),
    ("BlockComponents.Gain", "BlockComponents.Math.Gain"),
    ("BlockComponents.LimPID", "BlockComponents.Continuous.LimPID"),
    ("BlockComponents.And", "BlockComponents.Logical.And"),
    ("BlockComponents.Interpolation", "BlockComponents.Tables.Interpolation"),
    ("HydraulicComponents.FixedVolume", "HydraulicComponents.Vessels.FixedVolume"),
    ("HydraulicComponents.TwoPorts", "HydraulicComponents.Interfaces.TwoPorts"),
    ("HydraulicComponents.DoubleActingCylinder", "HydraulicComponents.Machines.DoubleActingCylinder"),
]


@pytest.fixture(scope="module")
def library():
    return Library()


@pytest.mark.parametrize("flat, documented", SPELLINGS, ids=[s[0] for s in SPELLINGS])
def test_the_flat_path_is_the_documented_definition(library, flat, documented):
    found = library.lookup(flat, "", None)
    assert found is library.lookup(documented, "", None)
    assert found.qualified_name == documented
    expected_file = COMPONENTS.joinpath(*documented.split(".")).with_suffix(".dyad")
    assert Path(found.definition.span.file) == expected_file


def test_thermal_flat_paths_are_the_earlier_library_not_aliases(library):
    # Dyad's earlier ThermalComponents (flat, Node connectors with Q) and the documented one
    # (subpackages, HeatPort with Q_flow) are two components: a definition at the flat path wins
    flat = library.lookup("ThermalComponents.HeatCapacitor", "", None)
    documented = library.lookup("ThermalComponents.Components.HeatCapacitor", "", None)
    assert flat.qualified_name == "ThermalComponents.HeatCapacitor"
    assert flat.definition is not documented.definition


def bare_extension_of_own_package(path: Path) -> str | None:
    """The base a file's definition merely re-declares under its own name inside its own top-level
    package (the removed second alias mechanism), or None."""
    (definition, *_) = parser.parse_file(str(path)).definitions
    package = path.relative_to(COMPONENTS).parts[0]
    if not isinstance(definition, ast.ComponentDef) or definition.declarations or definition.relations or len(definition.extends) != 1:
        return None
    base = definition.extends[0].type_name
    same_package = base.split(".")[0] == package or "." not in base
    return base if same_package and base.split(".")[-1] == definition.name else None


def test_no_file_re_declares_a_component_of_its_own_package():
    files = sorted(p for package in STANDARD_PACKAGES for p in (COMPONENTS / package).rglob("*.dyad"))
    assert len(files) > 150
    assert [(p.relative_to(COMPONENTS).as_posix(), base) for p in files
            if (base := bare_extension_of_own_package(p))] == []


def test_both_spellings_flatten_to_the_same_equations():
    flat = flatten_model("RotationalComponents.IdealGear")
    documented = flatten_model("RotationalComponents.Components.IdealGear")
    assert [str(e.residual) for e in flat.equations] == [str(e.residual) for e in documented.equations]


def test_an_error_in_a_component_named_flat_points_at_its_documented_file(tmp_path):
    model = tmp_path / "NoValue.dyad"
    model.write_text("component NoValue\n  r = ElectricalComponents.Resistor()\n"
                     "  g = ElectricalComponents.Ground()\nrelations\n"
                     "  connect(r.p, g.g)\n  connect(r.n, g.g)\nend\n")
    with pytest.raises(DyadError) as err:
        require_parameter_values(flatten_model(str(model)))
    assert err.value.message == "parameter `r.R` of `NoValue` has no value"
    assert Path(err.value.span.file) == COMPONENTS / "ElectricalComponents/Analog/Basic/Resistor.dyad"
    assert (err.value.span.line, err.value.span.column) == (5, 3)


def write(path, text):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


def test_the_alias_reaches_nested_subpackages_and_is_refused_when_ambiguous(tmp_path):
    write(tmp_path / "P" / "A" / "B" / "X.dyad", "component X\nend\n")
    write(tmp_path / "P" / "A" / "Y.dyad", "component Y\nend\n")
    write(tmp_path / "P" / "C" / "D" / "Y.dyad", "component Y\nend\n")
    library = Library([tmp_path])
    assert library.lookup("P.X", "", None).qualified_name == "P.A.B.X"
    assert library.lookup("P.A.X", "", None).qualified_name == "P.A.B.X"
    assert library.lookup("P.Y", "", None) is None
    with pytest.raises(DyadError) as err:
        library.resolve("P.Y", "", None, None, what="component type")
    assert err.value.hint == ("`P.Y` is defined in more than one subpackage of `P`; name one: "
                              "`P.A.Y`, `P.C.D.Y`")
