"""modelDescription.xml of an FMI 2.0 Model Exchange FMU: the variables with causality,
variability and start values (the -p values are start values of settable parameters), units from
the declared types (with their SI base units), descriptions from the doc strings, and the model
structure: outputs, derivatives with the states and inputs each depends on (dependencies.py).
"""
from __future__ import annotations

import datetime
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from fractions import Fraction
from typing import Mapping

from compiler.fmu.dependencies import derivative_dependencies
from compiler.fmu.layout import INPUT, PARAMETER, FmuLayout
from compiler.runtime import CompiledModel
from compiler.units.quantity import DIMENSIONS
from compiler.units.system import is_offset_unit, parse_unit


DEFAULT_TOLERANCE = 1e-6     # the C runtime's DY_DEFAULT_TOLERANCE: the Co-Simulation integrator's


@dataclass(frozen=True)
class ModelInfo:
    """What the description says besides the compiled model: its identifier, GUID, doc strings
    (name -> text), declared units (name -> unit), the tool's version."""
    identifier: str
    guid: str
    description: str
    descriptions: Mapping[str, str]
    units: Mapping[str, str]
    tool: str
    stop_time: float | None = None
    kind: str = "me"             # "me": Model Exchange, "cs": Co-Simulation


def _variable(parent, name: str, reference: int, info: ModelInfo, unit: str | None = None, *,
              real: Mapping[str, str] | None = None, **attributes: str) -> ET.Element:
    element = ET.SubElement(parent, "ScalarVariable", {"name": name, "valueReference": str(reference)})
    if info.descriptions.get(name):
        element.set("description", info.descriptions[name])
    for key, value in attributes.items():
        element.set(key, value)
    settings = dict(real or {})
    if unit:
        settings["unit"] = unit
    ET.SubElement(element, "Real", settings)
    return element


def _unit_definitions(root, units: set[str]) -> None:
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


def model_description(model: CompiledModel, layout: FmuLayout, info: ModelInfo) -> str:
    root = ET.Element("fmiModelDescription", {
        "fmiVersion": "2.0", "modelName": model.name, "guid": info.guid, "description": info.description,
        "generationTool": info.tool, "variableNamingConvention": "flat",
        "generationDateAndTime": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "numberOfEventIndicators": str(layout.event_count)})
    capabilities = {"modelIdentifier": info.identifier, "canGetAndSetFMUstate": "true",
                    "providesDirectionalDerivative": "true", "canNotUseMemoryManagementFunctions": "true"}
    if info.kind == "cs":
        capabilities["canHandleVariableCommunicationStepSize"] = "true"
    interface = ET.SubElement(root, "CoSimulation" if info.kind == "cs" else "ModelExchange", capabilities)
    sources = ET.SubElement(interface, "SourceFiles")
    from compiler.fmu.sources import COMPILED_FILES
    for name in COMPILED_FILES:
        ET.SubElement(sources, "File", {"name": name})
    variables = ET.Element("ModelVariables")
    index, used_units = _add_variables(variables, model, layout, info)
    _unit_definitions(root, used_units)
    experiment = {"startTime": "0.0", "tolerance": repr(DEFAULT_TOLERANCE)}
    if info.stop_time is not None:
        experiment["stopTime"] = repr(float(info.stop_time))
    ET.SubElement(root, "DefaultExperiment", experiment)
    root.append(variables)
    _model_structure(root, model, layout, index)
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _add_variables(parent, model: CompiledModel, layout: FmuLayout, info: ModelInfo):
    """Every variable in value-reference order; returns (name -> 1-based index, units used)."""
    index: dict[str, int] = {}
    units: set[str] = set()
    outputs = set(layout.output_names)

    def add(name, reference, unit=None, **kwargs):
        if name in index:
            return
        _variable(parent, name, reference, info, unit, **kwargs)
        index[name] = len(index) + 1
        if unit:
            units.add(unit)

    for i, name in enumerate(model.state_names):
        add(name, layout.state_reference(i), info.units.get(name),
            causality="output" if name in outputs else "local", variability="continuous", initial="calculated")
    for i, name in enumerate(model.state_names):
        add(f"der({name})", layout.derivative_reference(model, i), _rate_unit(info.units.get(name)),
            real={"derivative": str(index[name])}, causality="local", variability="continuous",
            initial="calculated")
    for name in model.output_names:
        add(name, layout.output_reference(model, name), info.units.get(name),
            causality="output" if name in outputs else "local", variability="continuous", initial="calculated")
    for i, name in enumerate(model.parameter_names):
        reference, unit, start = layout.parameter_reference(model, i), info.units.get(name), layout.parameter_values[i]
        if layout.settable[i] == PARAMETER:
            add(name, reference, unit, real={"start": repr(start)}, causality="parameter", variability="fixed",
                initial="exact")
        elif layout.settable[i] == INPUT:
            add(name, reference, unit, real={"start": repr(start)}, causality="input", variability="continuous")
        elif not name.startswith("__"):
            add(name, reference, unit, causality="calculatedParameter", variability="fixed", initial="calculated")
    return index, units


def _derivatives(derivatives, model: CompiledModel, layout: FmuLayout, index: Mapping[str, int]) -> None:
    """Each derivative with the states and inputs it depends on."""
    depends = derivative_dependencies(model, layout)
    inputs = [model.parameter_names[i] for i in layout.input_parameters]
    known = [index[n] for n in model.state_names] + [index[n] for n in inputs]
    for i, name in enumerate(model.state_names):
        used = sorted(known[j] for j in depends[i])
        unknown = ET.SubElement(derivatives, "Unknown", {"index": str(index[f"der({name})"]),
                                                         "dependencies": " ".join(map(str, used))})
        if used:
            unknown.set("dependenciesKind", " ".join(["dependent"] * len(used)))


def _rate_unit(unit: str | None) -> str | None:
    """The unit of a state's derivative: its own per second (`m` -> `m/s`, `m/s` -> `m/s/s`);
    none for an offset unit (degC) or one the unit system does not read."""
    if not unit or is_offset_unit(unit):
        return None
    rate = f"{unit}/s"
    try:
        parse_unit(rate)
    except ValueError:
        return None
    return rate


def _model_structure(root, model: CompiledModel, layout: FmuLayout, index: Mapping[str, int]) -> None:
    structure = ET.SubElement(root, "ModelStructure")
    if layout.output_names:              # an empty <Outputs> is not valid FMI 2.0
        outputs = ET.SubElement(structure, "Outputs")
        for name in sorted(layout.output_names, key=index.__getitem__):
            ET.SubElement(outputs, "Unknown", {"index": str(index[name])})
    if model.state_names:                # an empty <Derivatives> is not valid either
        _derivatives(ET.SubElement(structure, "Derivatives"), model, layout, index)
    calculated = [n for n in index if n in layout.output_names or n in model.state_names
                  or n.startswith("der(") and n[4:-1] in model.state_names]
    calculated += [model.parameter_names[i] for i, s in enumerate(layout.settable)
                   if s == 0 and not model.parameter_names[i].startswith("__")]
    if calculated:
        initial = ET.SubElement(structure, "InitialUnknowns")
        for name in sorted(set(calculated), key=index.__getitem__):
            ET.SubElement(initial, "Unknown", {"index": str(index[name])})
