"""The index-1 system with its algebraic unknowns eliminated through exact Jacobians.

A compiled model is der(x) = f(x, z, p, t), 0 = g(x, z, p, t), y = h(x, z, p, t), with g regular
in z (index 1). Some entries of p are inputs u (free top-level inputs, analysis-point
perturbations). At a point where g = 0, the implicit function theorem gives dz = -g_z^-1 (g_x dx +
g_u du), so

    A = f_x - f_z g_z^-1 g_x     B = f_u - f_z g_z^-1 g_u
    C = h_x - h_z g_z^-1 g_x     D = h_u - h_z g_z^-1 g_u

with every partial derivative from CasADi's algorithmic differentiation (no finite differences).
`EliminatedSystem` is the small API that linearization, FMU directional derivatives and a native
run loop share: solve the algebraic part by Newton with the exact Jacobian, then return these
Jacobians at (x, u, p, t).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import casadi as ca
import numpy as np

from compiler.runtime import CompiledModel


class AlgebraicSolveFailed(ValueError):
    """Newton on the algebraic equations did not converge (or g_z is singular) at the point."""


@dataclass(frozen=True)
class Jacobians:
    """The eliminated Jacobians at one point, plus the values there."""
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    derivatives: np.ndarray      # der(x) at the point
    outputs: np.ndarray          # y at the point
    z: np.ndarray                # the algebraic unknowns solved at the point


class EliminatedSystem:
    """The Jacobians of der(x) and of chosen outputs w.r.t. states x and inputs u of `model`.

    `input_indices`: positions in the model's parameter vector that are inputs; `output_names`:
    names among `model.output_names`. The CasADi function is built once per instance."""

    def __init__(self, model: CompiledModel, input_indices: Sequence[int], output_names: Sequence[str]):
        self.model = model
        self.input_indices = [int(i) for i in input_indices]
        self.output_rows = [model.output_index(name) for name in output_names]
        self._function = self._build()

    def _build(self) -> ca.Function:
        model = self.model
        x, z, p, t = model.symbols()
        ode, alg = model.dae(x, z, p, t)
        outputs = model.outputs(x, z, p, t)
        y = ca.vertcat(*[outputs[i] for i in self.output_rows]) if self.output_rows else ca.SX(0, 1)
        u = ca.vertcat(*[p[i] for i in self.input_indices]) if self.input_indices else ca.SX(0, 1)
        # one Jacobian of every row w.r.t. every unknown: one AD sweep, split after evaluation
        whole = ca.jacobian(ca.vertcat(ode, alg, y), ca.vertcat(x, z, u))
        return ca.Function("eliminated_jacobians", [x, z, p, t], [ode, alg, y, whole])

    def function(self) -> ca.Function:
        """(x, z, p, t) -> (ode, alg, y, d(ode; alg; y) / d(x; z; u)): what the Jacobians are
        made of, for callers that evaluate it elsewhere (an FMU's C code, compiler/fmu/)."""
        return self._function

    def solve_algebraic(self, x: np.ndarray, p: np.ndarray, t: float, z_guess: np.ndarray,
                        tol: float = 1e-12, max_iterations: int = 50) -> np.ndarray:
        """z with g(x, z, p, t) = 0 by Newton with the exact Jacobian g_z, from `z_guess`."""
        z = np.asarray(z_guess, dtype=float).copy()
        if not len(z):
            return z
        newton = self.model.algebraic_newton()
        for _ in range(max_iterations):
            r, jac = newton(x, z, p, t)
            r = np.asarray(r, dtype=float).reshape(-1)
            if not np.all(np.isfinite(r)):
                raise AlgebraicSolveFailed("the algebraic equations are not finite at the point")
            jac = np.asarray(ca.densify(jac), dtype=float)
            try:
                step = np.linalg.solve(jac, r)
            except np.linalg.LinAlgError:
                raise AlgebraicSolveFailed("the algebraic equations are singular in the algebraic "
                                           "unknowns at the point (not index 1 there)") from None
            z = z - step
            if np.max(np.abs(step), initial=0.0) <= tol * (1.0 + np.max(np.abs(z), initial=0.0)):
                return z
        raise AlgebraicSolveFailed(f"Newton on the algebraic equations did not converge in "
                                   f"{max_iterations} iterations (last step {np.max(np.abs(step)):.3g})")

    def jacobians(self, x: np.ndarray, z: np.ndarray, p: np.ndarray, t: float) -> Jacobians:
        """A, B, C, D at (x, z, p, t); z must solve the algebraic equations there."""
        values = [np.asarray(ca.densify(v), dtype=float) for v in self._function(x, z, p, t)]
        ode, alg, y = (v.reshape(-1) for v in values[:3])
        rows = np.cumsum([len(ode), len(alg)])
        columns = np.cumsum([len(x), len(z)])
        (fx, fz, fu), (gx, gz, gu), (hx, hz, hu) = (np.hsplit(block, columns)
                                                    for block in np.vsplit(values[3], rows))
        if gz.size:
            try:
                eliminated = np.linalg.solve(gz, np.hstack([gx, gu]))
            except np.linalg.LinAlgError:
                raise AlgebraicSolveFailed("the algebraic equations are singular in the algebraic "
                                           "unknowns at the point (not index 1 there)") from None
            zx, zu = eliminated[:, :gx.shape[1]], eliminated[:, gx.shape[1]:]
            fx, fu = fx - fz @ zx, fu - fz @ zu
            hx, hu = hx - hz @ zx, hu - hz @ zu
        return Jacobians(fx, fu, hx, hu, ode, y, np.asarray(z, dtype=float))

    def at(self, x: np.ndarray, p: np.ndarray, t: float, z_guess: np.ndarray) -> Jacobians:
        """Solve the algebraic part at (x, p, t), then the Jacobians there."""
        z = self.solve_algebraic(np.asarray(x, dtype=float), p, t, z_guess)
        return self.jacobians(np.asarray(x, dtype=float), z, p, t)

    def with_inputs(self, p: np.ndarray, u: np.ndarray) -> np.ndarray:
        """The parameter vector p with the inputs set to u (a new vector)."""
        full = np.array(p, dtype=float)
        full[self.input_indices] = np.asarray(u, dtype=float).reshape(-1)
        return full

    def evaluate(self, x: np.ndarray, u: np.ndarray, p: np.ndarray, t: float,
                 z_guess: np.ndarray | None = None) -> Jacobians:
        """At states x, inputs u, parameters p (the inputs' entries are replaced), time t: the
        algebraic unknowns by Newton, der(x), the outputs and the eliminated Jacobians (what an
        FMU's fmi2GetDirectionalDerivative needs, as products with a seed vector)."""
        guess = np.asarray(self.model.z_guess if z_guess is None else z_guess, dtype=float)
        return self.at(x, self.with_inputs(p, u), t, guess)
