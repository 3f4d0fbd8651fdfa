"""The FlatSystem: one model as plain variables, parameters and sympy residual equations.

Conventions every later stage relies on:
- Every scalar unknown has a dotted name (`boom.frame_a.x`, array elements `g_vec[1]`, 1-based).
- Its sympy symbol is `sympy.Symbol(name)`; its time derivative is `sympy.Symbol(der_name(name))`,
  i.e. `der(boom.phi)`. `FlatSystem.derivatives` maps every derivative name that occurs to the name
  of the variable it differentiates; a derivative is an unknown of its own (not a Variable entry).
- Parameters are `sympy.Symbol(name)` too; the independent variable is `TIME` (`time`).
- Equations are residuals: `lhs - rhs`, meaning `residual = 0`.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy

from compiler.errors import Span, display_path

TIME = sympy.Symbol("time")

# Variable kinds
STATE_CANDIDATE = "state_candidate"   # appears differentiated somewhere
ALGEBRAIC = "algebraic"
INPUT = "input"                       # top-level input signal (an unconnected input of the model)
OUTPUT = "output"                     # an output signal


def der_name(name: str) -> str:
    return f"der({name})"


@dataclass(frozen=True)
class Origin:
    """Where something came from: the component instance path ('' = the model) and a source span."""
    path: str
    span: Span | None = None

    def describe(self) -> str:
        """For labels that outlive this machine (generated modules): no absolute paths."""
        where = self.path or "<model>"
        if not self.span:
            return where
        return f"{where} ({display_path(self.span.file)}:{self.span.line}:{self.span.column})"


@dataclass
class Variable:
    name: str
    kind: str = ALGEBRAIC
    units: str | None = None
    start: float | None = None          # value of `initial`/`= initial`; also an initial equation
    guess: float | None = None          # iteration seed only
    state_priority: int = 0             # > 0 prefer as state, < 0 avoid (Modelica stateSelect)
    description: str | None = None
    origin: Origin = field(default_factory=lambda: Origin(""))


@dataclass
class Parameter:
    name: str
    value: float | None                 # numeric value after evaluating `default` in dependency order
    default: sympy.Expr | None = None   # the binding expression, possibly in other parameters' symbols
    tunable: bool = True                # False for final / structural / constant
    variability: str = "parameter"      # 'parameter' | 'structural' | 'constant'
    units: str | None = None
    description: str | None = None
    origin: Origin = field(default_factory=lambda: Origin(""))
    type_name: str = "Real"             # as declared, e.g. `Resistance`
    instance_span: Span | None = None   # where its component is instantiated (`r = Resistor()`)


@dataclass
class Equation:
    residual: sympy.Expr
    origin: Origin
    kind: str = "equation"              # 'equation' | 'binding' | 'connect' | 'flow' | 'unconnected_flow'
    description: str | None = None


@dataclass
class FlatSystem:
    name: str
    variables: list[Variable]
    parameters: list[Parameter]
    equations: list[Equation]
    initial_equations: list[Equation] = field(default_factory=list)
    derivatives: dict[str, str] = field(default_factory=dict)   # 'der(x)' -> 'x'
    guesses: dict[str, float] = field(default_factory=dict)
    metadata: dict = field(default_factory=dict)                # tests, render info: not numerics
    visual: dict = field(default_factory=dict)                  # render info per instance path
    warnings: list[str] = field(default_factory=list)
    unit_findings: list | None = None       # compiler.units findings; None: not checked (--units off)

    def variable(self, name: str) -> Variable:
        for v in self.variables:
            if v.name == name:
                return v
        raise KeyError(name)

    def parameter_values(self) -> dict[str, float]:
        return {p.name: p.value for p in self.parameters if p.value is not None}

    def initial_values(self) -> dict[str, float]:
        """The one start-value rule: what is known of each unknown before any solve, for the
        initialization's first iterate and for the state choice at the start. An explicit
        `guess x = v` relation wins, then the variable's guess, then its start value."""
        values = {}
        for v in self.variables:
            for value in (v.guess, v.start):
                if value is not None:
                    values[v.name] = float(value)
                    break
        values.update({k: float(v) for k, v in self.guesses.items()})
        return values
