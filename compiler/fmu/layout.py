"""What an FMU exposes of a compiled model: its inputs (free top-level inputs, parameters of the
compiled model), its outputs (top-level outputs), the start values of its parameters (the -p
values applied, not baked in), which parameters an importer may set, and its value references.

Value references follow the C runtime (fmu_model.c): the states 0..nx-1, their derivatives
nx..2nx-1, the rows of the model's output function from 2nx, its parameter vector, the event
indicators (FMI 3.0 lists them as variables), then time (FMI 3.0's independent variable).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

import numpy as np

from compiler.runtime import CompiledModel

NOT_SETTABLE, PARAMETER, INPUT = 0, 1, 2


@dataclass(frozen=True)
class FmuLayout:
    input_parameters: list[int]      # positions in the parameter vector that are FMU inputs
    output_names: list[str]          # names among model.output_names that are FMU outputs
    parameter_start: list[float]     # the parameter vector the FMU starts from (-p applied)
    parameter_mask: list[float]      # 1 where a value was given (-p), so it is not re-derived
    parameter_values: list[float]    # every parameter's value with those (dependent ones derived)
    settable: list[int]              # per parameter: NOT_SETTABLE, PARAMETER or INPUT
    event_count: int
    time_event_count: int

    def state_reference(self, i: int) -> int:
        return i

    def derivative_reference(self, model: CompiledModel, i: int) -> int:
        return len(model.state_names) + i

    def output_reference(self, model: CompiledModel, name: str) -> int:
        return 2 * len(model.state_names) + model.output_index(name)

    def parameter_reference(self, model: CompiledModel, i: int) -> int:
        return 2 * len(model.state_names) + len(model.output_names) + i

    def indicator_reference(self, model: CompiledModel, k: int) -> int:
        return self.parameter_reference(model, len(model.parameter_names)) + k

    def time_reference(self, model: CompiledModel) -> int:
        return self.indicator_reference(model, self.event_count)


def fmu_layout(model: CompiledModel, inputs: Sequence[str], outputs: Sequence[str],
               overrides: Mapping[str, float]) -> FmuLayout:
    """`inputs`: parameter names that are inputs; `outputs`: output names; `overrides`: the -p
    values (checked here: an unknown or final parameter is a ModelInputError)."""
    values = model.parameter_vector(overrides)
    index = {n: i for i, n in enumerate(model.parameter_names)}
    start = np.array(model.parameter_defaults, dtype=float)
    mask = np.zeros(len(start))
    for name, value in overrides.items():
        start[index[name]] = float(value)
        mask[index[name]] = 1.0
    input_parameters = [index[n] for n in inputs]
    settable = [PARAMETER if tunable and not name.startswith("__") else NOT_SETTABLE
                for name, tunable in zip(model.parameter_names, model.parameter_tunable)]
    for i in input_parameters:
        settable[i] = INPUT
    events = model.events.numel_out() if model.events is not None else 0
    time_events = model.time_events.size1_out(0) if model.time_events is not None else 0
    return FmuLayout(input_parameters, list(outputs), [float(v) for v in start], [float(v) for v in mask],
                     [float(v) for v in values], settable, int(events), int(time_events))
