"""The linear model at an operating point: (A, B, C, D) with the names of its states, inputs and
outputs and the point it was taken at; its minimal realization; conversion to python-control.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from compiler.linear.elimination import EliminatedSystem
from compiler.linear.operating_point import OperatingPoint
from compiler.runtime import ModelInputError


@dataclass(frozen=True)
class LinearSystem:
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    states: list[str]
    inputs: list[str]
    outputs: list[str]
    time: float
    state_values: dict[str, float] = field(default_factory=dict)
    input_values: dict[str, float] = field(default_factory=dict)
    parameter_values: dict[str, float] = field(default_factory=dict)
    steady_residual: float | None = None
    minimal: bool = False

    def operating_point(self) -> dict:
        return {"time": self.time, "states": dict(self.state_values), "inputs": dict(self.input_values),
                "parameters": dict(self.parameter_values)}

    def poles(self) -> np.ndarray:
        return np.linalg.eigvals(self.A) if self.A.size else np.zeros(0, dtype=complex)

    def dc_gain(self) -> np.ndarray:
        """-C A^-1 B + D; inf where A is singular (an integrator between input and output)."""
        if not self.A.size:
            return self.D.copy()
        try:
            return self.D - self.C @ np.linalg.solve(self.A, self.B)
        except np.linalg.LinAlgError:
            return np.full(self.D.shape, np.inf)

    def to_control(self):
        import control
        return control.ss(self.A, self.B, self.C, self.D, inputs=list(self.inputs),
                          outputs=list(self.outputs), states=list(self.states) or None)

    def minimal_realization(self, tol: float | None = None) -> "LinearSystem":
        """The minimal realization (python-control's minreal: uncontrollable and unobservable
        modes removed); its states are new coordinates named x1, x2, ..."""
        import control
        if not self.A.size:
            return dataclasses.replace(self, minimal=True)
        reduced = control.minreal(control.ss(self.A, self.B, self.C, self.D), tol=tol, verbose=False)
        n = reduced.A.shape[0]
        return dataclasses.replace(self, A=np.asarray(reduced.A), B=np.asarray(reduced.B),
                                   C=np.asarray(reduced.C), D=np.asarray(reduced.D),
                                   states=[f"x{k + 1}" for k in range(n)], minimal=True)

    def select(self, inputs: Sequence[int] | None = None, outputs: Sequence[int] | None = None
               ) -> "LinearSystem":
        ins = list(range(len(self.inputs))) if inputs is None else list(inputs)
        outs = list(range(len(self.outputs))) if outputs is None else list(outputs)
        return dataclasses.replace(self, B=self.B[:, ins], C=self.C[outs, :], D=self.D[np.ix_(outs, ins)],
                                   inputs=[self.inputs[i] for i in ins],
                                   outputs=[self.outputs[i] for i in outs])


def linearize_at(point: OperatingPoint, inputs: Sequence[str], outputs: Sequence[str],
                 output_labels: Sequence[str] | None = None) -> LinearSystem:
    """(A, B, C, D) of `point.model` at `point`: inputs are parameter names of the model, outputs
    names among its outputs (`output_labels`: what to call them, e.g. an analysis point's name)."""
    model = point.model
    index = {name: i for i, name in enumerate(model.parameter_names)}
    for name in inputs:
        if name not in index:
            raise ModelInputError(f"'{name}' is not an input of model {model.name}")
    system = model.derived(("eliminated", tuple(inputs), tuple(outputs)),
                           lambda: EliminatedSystem(model, [index[n] for n in inputs], outputs))
    jac = system.jacobians(point.x, point.z, point.p, point.time)
    input_names = set(inputs)
    return LinearSystem(
        jac.A, jac.B, jac.C, jac.D, list(model.state_names), list(inputs),
        list(output_labels or outputs), point.time,
        state_values=dict(zip(model.state_names, map(float, point.x))),
        input_values={n: float(point.p[index[n]]) for n in inputs},
        parameter_values={n: float(v) for n, v in zip(model.parameter_names, point.p) if n not in input_names},
        steady_residual=point.steady_residual)
