"""What an FMU's modelDescription.xml says, whatever its FMI version: the variables with causality,
variability, initial and start values (the -p values are start values of settable parameters),
units from the declared types, descriptions from the doc strings, and the model structure
(outputs, each derivative with the states and inputs it depends on, the initial unknowns).
description.py writes it as FMI 2.0, description3.py as FMI 3.0.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

from compiler.fmu.dependencies import derivative_dependencies
from compiler.fmu.layout import INPUT, NOT_SETTABLE, PARAMETER, FmuLayout
from compiler.runtime import CompiledModel
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


@dataclass(frozen=True)
class FmuVariable:
    name: str
    reference: int
    causality: str
    variability: str
    initial: str | None = None
    unit: str | None = None
    start: float | None = None
    derivative_of: str | None = None     # a derivative's state
    description: str | None = None
    minimum: float | None = None         # the declared bounds (checked inside the FMU)
    maximum: float | None = None


@dataclass(frozen=True)
class FmuStructure:
    outputs: list[str]                          # in variable order
    derivatives: list[tuple[str, list[str]]]    # each derivative with the states and inputs it depends on
    initial_unknowns: list[str]                 # in variable order


def rate_unit(unit: str | None) -> str | None:
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


def fmu_variables(model: CompiledModel, layout: FmuLayout, info: ModelInfo) -> list[FmuVariable]:
    """Every variable in value-reference order (each name once)."""
    found: dict[str, FmuVariable] = {}
    outputs = set(layout.output_names)
    bounds = model.metadata.get("bounds") or {}

    def add(name, reference, causality, variability, initial=None, unit=None, **kwargs):
        if name not in found:
            limits = bounds.get(name, {})
            found[name] = FmuVariable(name, reference, causality, variability, initial, unit,
                                      description=info.descriptions.get(name) or None, minimum=limits.get("min"),
                                      maximum=limits.get("max"), **kwargs)

    for i, name in enumerate(model.state_names):
        add(name, layout.state_reference(i), "output" if name in outputs else "local", "continuous", "calculated",
            info.units.get(name))
    for i, name in enumerate(model.state_names):
        add(f"der({name})", layout.derivative_reference(model, i), "local", "continuous", "calculated",
            rate_unit(info.units.get(name)), derivative_of=name)
    for name in model.output_names:
        add(name, layout.output_reference(model, name), "output" if name in outputs else "local", "continuous",
            "calculated", info.units.get(name))
    for i, name in enumerate(model.parameter_names):
        reference, unit, start = layout.parameter_reference(model, i), info.units.get(name), layout.parameter_values[i]
        if layout.settable[i] == PARAMETER:
            add(name, reference, "parameter", "tunable", "exact", unit, start=start)
        elif layout.settable[i] == INPUT:
            add(name, reference, "input", "continuous", None, unit, start=start)
        elif not name.startswith("__"):       # may follow a tuned parameter
            add(name, reference, "calculatedParameter", "tunable", "calculated", unit)
    return list(found.values())


def fmu_structure(model: CompiledModel, layout: FmuLayout, variables: list[FmuVariable]) -> FmuStructure:
    """Outputs, derivatives with their dependencies (dependencies.py), and the initial unknowns:
    the states, derivatives and outputs (all calculated) and the calculated parameters."""
    depends = derivative_dependencies(model, layout)
    known = list(model.state_names) + [model.parameter_names[i] for i in layout.input_parameters]
    derivatives = [(f"der({name})", [known[j] for j in depends[i]]) for i, name in enumerate(model.state_names)]
    listed = {v.name for v in variables}
    calculated = set(layout.output_names) | set(model.state_names) | {f"der({n})" for n in model.state_names}
    calculated |= {model.parameter_names[i] for i, s in enumerate(layout.settable)
                   if s == NOT_SETTABLE and not model.parameter_names[i].startswith("__")}
    return FmuStructure([v.name for v in variables if v.causality == "output"], derivatives,
                        [v.name for v in variables if v.name in calculated and v.name in listed])
