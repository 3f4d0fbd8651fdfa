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
        """A python-control StateSpace (unnamed signals: its names may not hold dots)."""
        import control
        return control.ss(self.A, self.B, self.C, self.D)

    def minimal_realization(self, tol: float = 1e-9) -> "LinearSystem":
        """The minimal realization: the reachable part (orthonormal Krylov basis of (A, B)), then
        its observable part (the same on (A', C')); its states are new coordinates x1, x2, ...
        (python-control's minreal needs slycot, an optional Fortran package)."""
        reach = _krylov_basis(self.A, self.B, tol)
        a, b, c = reach.T @ self.A @ reach, reach.T @ self.B, self.C @ reach
        observe = _krylov_basis(a.T, c.T, tol)
        a, b, c = observe.T @ a @ observe, observe.T @ b, c @ observe
        return dataclasses.replace(self, A=a, B=b, C=c, D=self.D.copy(),
                                   states=[f"x{k + 1}" for k in range(a.shape[0])], minimal=True)

    def select(self, inputs: Sequence[int] | None = None, outputs: Sequence[int] | None = None
               ) -> "LinearSystem":
        ins = list(range(len(self.inputs))) if inputs is None else list(inputs)
        outs = list(range(len(self.outputs))) if outputs is None else list(outputs)
        return dataclasses.replace(self, B=self.B[:, ins], C=self.C[outs, :], D=self.D[np.ix_(outs, ins)],
                                   inputs=[self.inputs[i] for i in ins],
                                   outputs=[self.outputs[i] for i in outs])


def _krylov_basis(a: np.ndarray, b: np.ndarray, tol: float) -> np.ndarray:
    """An orthonormal basis of span[b, a b, a^2 b, ...] (rank decided by singular values above
    `tol` times the largest)."""
    n = a.shape[0]
    scale = max(np.abs(b).max(initial=0.0), np.abs(a).max(initial=0.0), 1e-300)
    basis = _orthonormal(b, tol * scale)
    while 0 < basis.shape[1] < n:
        grown = _orthonormal(np.hstack([basis, a @ basis]), tol * scale)
        if grown.shape[1] == basis.shape[1]:
            break
        basis = grown
    return basis


def _orthonormal(m: np.ndarray, threshold: float) -> np.ndarray:
    if not m.size:
        return np.zeros((m.shape[0], 0))
    u, sv, _ = np.linalg.svd(m, full_matrices=False)
    return u[:, :int(np.sum(sv > threshold))]


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
