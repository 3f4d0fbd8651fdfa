"""The standard package `Dyad` (components/Dyad/): its quantity types and connectors parse, are
defined once, carry units that compiler.units.system reads, cover every base type the published Dyad
libraries use, and are found from any package by their plain name."""
from __future__ import annotations

from pathlib import Path

import pytest

from compiler.api import flatten
from compiler.syntax import ast
from compiler.syntax.parser import parse_file
from compiler.units.system import UnitError, parse_unit

DYAD = Path(__file__).resolve().parents[2] / "components" / "Dyad"

# Every base type and connector that DyadLang's BlockComponents, ElectricalComponents,
# HydraulicComponents, TranslatedComponents and DyadExampleComponents use without defining it.
USED_BY_PUBLISHED_LIBRARIES = """
AbsolutePressure Acceleration Angle AngularAcceleration AngularVelocity Area Capacitance
Conductance CouplingCoefficient Current DampingCoefficient DecayConstant Density Distance
DynamicViscosity ElectricalTorqueConstant Force Frequency HeatCapacity HeatFlowRate Inductance
Inertia Length LinearTemperatureCoefficient MagneticFlux MagneticFluxDensity MagneticPotential
MagneticPotentialDifference Mass MassFlowRate Period Permeance Position Power Pressure Radius
RelativePermeability Reluctance Resistance RotationalDampingConstant RotationalSpringConstant
SoundPowerLevel Temperature TemperatureDifference TemperatureSlope ThermalConductance
ThermalResistance Time Torque TranslationalSpringConstant Velocity Voltage VoltageSlope Volume
Pin Spline Flange HeatPort Node RealInput RealOutput BooleanInput BooleanOutput IntegerInput
IntegerOutput Frame2D Frame3D EmptyComponent
""".split()


def definitions():
    found = {}
    for path in sorted(DYAD.glob("*.dyad")):
        for definition in parse_file(str(path)).definitions:
            found.setdefault(definition.name, []).append(path.name)
    return found


@pytest.fixture(scope="module")
def defined():
    return definitions()


def test_every_name_is_defined_once(defined):
    assert {name: files for name, files in defined.items() if len(files) > 1} == {}


def test_the_package_ships_about_five_hundred_quantity_types():
    types = [d for path in DYAD.glob("*.dyad") for d in parse_file(str(path)).definitions
             if isinstance(d, ast.TypeDef)]
    assert len(types) >= 490


def test_every_type_and_connector_the_published_libraries_use_is_there(defined):
    assert [name for name in USED_BY_PUBLISHED_LIBRARIES if name not in defined] == []


def test_every_unit_string_is_read_by_the_unit_parser():
    unreadable, checked = [], 0
    for path in sorted(DYAD.glob("*.dyad")):
        for definition in parse_file(str(path)).definitions:
            for mod in getattr(getattr(definition, "base", None), "modifications", None) or ():
                if mod.name == "units" and isinstance(mod.value, ast.String):
                    checked += 1
                    try:
                        parse_unit(mod.value.value)
                    except UnitError as err:
                        if "offset" not in str(err):        # degC parses; it only has an offset
                            unreadable.append((definition.name, mod.value.value, str(err)))
    assert unreadable == []
    assert checked >= 490


CONNECTOR_MODEL = """
"Every physical connector of Dyad, each on a one-port element whose equations fix it"
component UsesBaseConnectors
  "electrical"
  pin = Pin()
  "translational"
  flange = Flange()
  "rotational"
  spline = Spline()
  "thermal"
  port = HeatPort()
  "thermal (older name)"
  node = Node()
  "a quantity type"
  parameter v0::Voltage = 3
  "a quantity type from another domain file"
  parameter q0::MagneticFlux = 2
  "a length"
  parameter s0::Length = 2
relations
  pin.v = v0
  flange.s = s0
  spline.phi = 1
  port.T = 300
  node.T = 310
end
"""


def test_connectors_and_types_resolve_from_any_package_with_their_fields_and_units(tmp_path):
    model = tmp_path / "UsesBaseConnectors.dyad"
    model.write_text(CONNECTOR_MODEL)
    flat = flatten(str(model))
    units = {v.name: v.units for v in flat.variables}
    assert units == {"pin.v": "V", "pin.i": "A", "flange.s": "m", "flange.f": "N",
                     "spline.phi": "rad", "spline.tau": "N.m", "port.T": "K",
                     "port.Q_flow": "W", "node.T": "K", "node.Q": "W"}
    assert {p.name: p.units for p in flat.parameters} == {"v0": "V", "q0": "Wb", "s0": "m"}
