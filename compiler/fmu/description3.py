"""modelDescription.xml of an FMI 3.0 FMU (Model Exchange or Co-Simulation): what variables.py
decides, written as FMI 3.0 says: Float64 variables, the independent variable `time`, each event
indicator a variable of its own, and a model structure by value reference (outputs, continuous
state derivatives with their dependencies, initial unknowns, event indicators).
"""
from __future__ import annotations

import datetime
import xml.etree.ElementTree as ET
from typing import Sequence

from compiler.fmu.description import add_unit_definitions, number_attributes, variable_element
from compiler.fmu.layout import FmuLayout
from compiler.fmu.variables import DEFAULT_TOLERANCE, FmuVariable, ModelInfo, fmu_structure, fmu_variables
from compiler.runtime import CompiledModel

INDICATOR_NAME = "__event_indicator[{}]"


def _interface(root, info: ModelInfo) -> None:
    capabilities = {"modelIdentifier": info.identifier, "canGetAndSetFMUState": "true",
                    "canSerializeFMUState": "true", "providesDirectionalDerivatives": "true",
                    "providesAdjointDerivatives": "true"}
    if info.kind == "cs":
        capabilities["canHandleVariableCommunicationStepSize"] = "true"
    else:                                     # fmi3CompletedIntegratorStep checks the declared bounds
        capabilities["needsCompletedIntegratorStep"] = "true"
    ET.SubElement(root, "CoSimulation" if info.kind == "cs" else "ModelExchange", capabilities)


def _add_variable(parent, variable: FmuVariable, references: dict[str, int]) -> None:
    variable_element(parent, "Float64", variable).attrib.update(number_attributes(variable, references))


def fmi3_variables(model: CompiledModel, layout: FmuLayout, info: ModelInfo) -> list[FmuVariable]:
    """`time` (the independent variable), the FMU's variables, then the event indicators."""
    time = FmuVariable("time", layout.time_reference(model), "independent", "continuous", unit="s",
                       description="the independent variable")
    indicators = [FmuVariable(INDICATOR_NAME.format(k + 1), layout.indicator_reference(model, k), "local",
                              "continuous", "calculated",
                              description="a zero function of the model's events (a sign change is an event)")
                  for k in range(layout.event_count)]
    return [time, *fmu_variables(model, layout, info), *indicators]


def model_description(model: CompiledModel, layout: FmuLayout, info: ModelInfo, compiled: Sequence[str]) -> str:
    """The description; `compiled` (the C files) is not listed: FMI 3.0 describes sources in
    sources/buildDescription.xml, which dyadc does not write."""
    root = ET.Element("fmiModelDescription", {
        "fmiVersion": "3.0", "modelName": model.name, "instantiationToken": info.guid,
        "description": info.description, "generationTool": info.tool,
        "generationDateAndTime": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "variableNamingConvention": "flat"})
    _interface(root, info)
    variables = fmi3_variables(model, layout, info)
    add_unit_definitions(root, {v.unit for v in variables if v.unit})
    experiment = {"startTime": "0.0", "tolerance": repr(DEFAULT_TOLERANCE)}
    if info.stop_time is not None:
        experiment["stopTime"] = repr(float(info.stop_time))
    ET.SubElement(root, "DefaultExperiment", experiment)
    references = {v.name: v.reference for v in variables}
    listed = ET.SubElement(root, "ModelVariables")
    for variable in variables:
        _add_variable(listed, variable, references)
    _model_structure(root, model, layout, variables, references)
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _model_structure(root, model: CompiledModel, layout: FmuLayout, variables: list[FmuVariable],
                     references: dict[str, int]) -> None:
    structure = fmu_structure(model, layout, [v for v in variables if v.causality != "independent"])
    element = ET.SubElement(root, "ModelStructure")
    for name in structure.outputs:
        ET.SubElement(element, "Output", {"valueReference": str(references[name])})
    for name, depends in structure.derivatives:
        used = sorted(references[n] for n in depends)
        unknown = ET.SubElement(element, "ContinuousStateDerivative", {"valueReference": str(references[name]),
                                                                       "dependencies": " ".join(map(str, used))})
        if used:
            unknown.set("dependenciesKind", " ".join(["dependent"] * len(used)))
    for name in structure.initial_unknowns:
        ET.SubElement(element, "InitialUnknown", {"valueReference": str(references[name])})
    for k in range(layout.event_count):
        ET.SubElement(element, "EventIndicator", {"valueReference": str(references[INDICATOR_NAME.format(k + 1)])})
