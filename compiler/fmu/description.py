"""modelDescription.xml of an FMI 2.0 FMU (Model Exchange or Co-Simulation): what variables.py
decides, written as FMI 2.0 says (ScalarVariable elements, a model structure by variable index),
with the unit definitions (their SI base units) that FMI 3.0's description shares.
"""
from __future__ import annotations

import datetime
import xml.etree.ElementTree as ET
from fractions import Fraction
from typing import Mapping, Sequence

from compiler.fmu.layout import FmuLayout
from compiler.fmu.variables import DEFAULT_TOLERANCE, FmuVariable, ModelInfo, fmu_structure, fmu_variables
from compiler.runtime import CompiledModel
from compiler.units.quantity import DIMENSIONS
from compiler.units.system import is_offset_unit, parse_unit


def add_unit_definitions(root, units: set[str]) -> None:
    """<UnitDefinitions>: each unit used, with its SI base units where the unit system reads it."""
    if not units:
        return
    definitions = ET.SubElement(root, "UnitDefinitions")
    for name in sorted(units):
        unit = ET.SubElement(definitions, "Unit", {"name": name})
        try:
            parsed = parse_unit(name)
        except ValueError:
            continue
        exponents = dict(zip(DIMENSIONS, parsed.exponents), rad=Fraction(parsed.angle))
        if is_offset_unit(name) or any(Fraction(v).denominator != 1 for v in exponents.values()):
            continue
        base = {key: str(int(v)) for key, v in exponents.items() if v}
        if parsed.factor != 1.0:
            base["factor"] = repr(float(parsed.factor))
        ET.SubElement(unit, "BaseUnit", base)


def variable_element(parent, tag: str, variable: FmuVariable) -> ET.Element:
    """`variable`'s element (FMI 2.0 ScalarVariable, FMI 3.0 Float64) with the attributes the two
    versions share: name, value reference, description, causality, variability, initial."""
    element = ET.SubElement(parent, tag, {"name": variable.name, "valueReference": str(variable.reference)})
    if variable.description:
        element.set("description", variable.description)
    element.set("causality", variable.causality)
    element.set("variability", variable.variability)
    if variable.initial:
        element.set("initial", variable.initial)
    return element


def number_attributes(variable: FmuVariable, references: Mapping[str, int]) -> dict[str, str]:
    """The attributes of `variable`'s number (FMI 2.0 Real, FMI 3.0 Float64): derivative (the
    value reference of its state), start, unit, min, max."""
    number = {}
    if variable.derivative_of:
        number["derivative"] = str(references[variable.derivative_of])
    if variable.start is not None:
        number["start"] = repr(float(variable.start))
    if variable.unit:
        number["unit"] = variable.unit
    for key, value in (("min", variable.minimum), ("max", variable.maximum)):
        if value is not None:
            number[key] = repr(float(value))
    return number


def _add_variable(parent, variable: FmuVariable, states: Mapping[str, int]) -> None:
    ET.SubElement(variable_element(parent, "ScalarVariable", variable), "Real", number_attributes(variable, states))


def model_description(model: CompiledModel, layout: FmuLayout, info: ModelInfo, compiled: Sequence[str]) -> str:
    root = ET.Element("fmiModelDescription", {
        "fmiVersion": "2.0", "modelName": model.name, "guid": info.guid, "description": info.description,
        "generationTool": info.tool, "variableNamingConvention": "flat",
        "generationDateAndTime": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "numberOfEventIndicators": str(layout.event_count)})
    capabilities = {"modelIdentifier": info.identifier, "canGetAndSetFMUstate": "true", "canSerializeFMUstate": "true",
                    "providesDirectionalDerivative": "true", "canNotUseMemoryManagementFunctions": "true"}
    if info.kind == "cs":
        capabilities["canHandleVariableCommunicationStepSize"] = "true"
    interface = ET.SubElement(root, "CoSimulation" if info.kind == "cs" else "ModelExchange", capabilities)
    sources = ET.SubElement(interface, "SourceFiles")
    for name in compiled:
        ET.SubElement(sources, "File", {"name": name})
    variables = fmu_variables(model, layout, info)
    add_unit_definitions(root, {v.unit for v in variables if v.unit})
    experiment = {"startTime": "0.0", "tolerance": repr(DEFAULT_TOLERANCE)}
    if info.stop_time is not None:
        experiment["stopTime"] = repr(float(info.stop_time))
    ET.SubElement(root, "DefaultExperiment", experiment)
    index = {v.name: k + 1 for k, v in enumerate(variables)}
    listed = ET.SubElement(root, "ModelVariables")
    for variable in variables:
        _add_variable(listed, variable, index)
    _model_structure(root, fmu_structure(model, layout, variables), index)
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _model_structure(root, structure, index: Mapping[str, int]) -> None:
    """Outputs, derivatives and initial unknowns by variable index (empty lists left out: an empty
    <Outputs> or <Derivatives> is not valid FMI 2.0)."""
    element = ET.SubElement(root, "ModelStructure")
    if structure.outputs:
        outputs = ET.SubElement(element, "Outputs")
        for name in structure.outputs:
            ET.SubElement(outputs, "Unknown", {"index": str(index[name])})
    if structure.derivatives:
        derivatives = ET.SubElement(element, "Derivatives")
        for name, depends in structure.derivatives:
            used = sorted(index[n] for n in depends)
            unknown = ET.SubElement(derivatives, "Unknown", {"index": str(index[name]),
                                                             "dependencies": " ".join(map(str, used))})
            if used:
                unknown.set("dependenciesKind", " ".join(["dependent"] * len(used)))
    if structure.initial_unknowns:
        initial = ET.SubElement(element, "InitialUnknowns")
        for name in structure.initial_unknowns:
            ET.SubElement(initial, "Unknown", {"index": str(index[name])})
