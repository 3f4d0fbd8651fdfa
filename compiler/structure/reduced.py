"""The ReducedSystem: an index-1 semi-explicit DAE ready to lower to CasADi.

    der(x) = ode(x, z, p, t)        one expression per state
         0 = alg(x, z, p, t)        one residual per algebraic unknown z

Expressions are sympy in the symbols of: states `x`, algebraic unknowns `z`, parameters `p`,
`TIME`, and the targets of `assignments` (each computed, in order, from x, z, p, t and the targets
of earlier assignments). Lowering inlines assignments as shared CasADi subexpressions.
`observables` are evaluated after the solve only (pruned from the integrated system); they may use
everything above and earlier observables. Names follow `compiler.model.flat` (`der(x)` for derivatives).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy

from compiler.model.flat import Origin


@dataclass
class Assignment:
    target: str
    expr: sympy.Expr
    origin: Origin | None = None


@dataclass
class ParameterInfo:
    name: str
    value: float                          # default numeric value
    binding: sympy.Expr | None = None     # default as an expression of earlier parameters (or None)
    tunable: bool = True


@dataclass
class InitialProblem:
    """Consistent initialization at t = t0: find x, z with `residuals(x, z, p, t0) = 0`.

    `residuals` = the DAE's `alg` plus the initial equations (derivatives already replaced by their
    `ode` expressions). It may have more residuals than unknowns (consistent redundant conditions);
    solve it in the least-squares sense and check the residual.
    """
    residuals: list[sympy.Expr]
    origins: list[Origin | None]
    guesses: dict[str, float] = field(default_factory=dict)   # seeds for x and z
    # Under-determined initialization: unknowns the initial conditions left free, fixed at these
    # start values / guesses (their rows are among `residuals`); reported as a note.
    chosen: dict[str, float] = field(default_factory=dict)


@dataclass
class ReducedSystem:
    name: str
    states: list[str]
    ode: list[sympy.Expr]                  # der(states[i]) = ode[i]
    algebraics: list[str]
    alg: list[sympy.Expr]                  # 0 = alg[j]
    assignments: list[Assignment]
    observables: list[Assignment]
    parameters: list[ParameterInfo]
    initial: InitialProblem
    output_names: list[str] = field(default_factory=list)     # every named signal, CSV order
    alg_origins: list[Origin | None] = field(default_factory=list)
    statistics: dict = field(default_factory=dict)            # counts per pass, index, ...
    metadata: dict = field(default_factory=dict)
