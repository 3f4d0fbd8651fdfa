"""Inputs of a linearization, made from the flat model: free top-level inputs and analysis points.

A top-level `input` left open becomes a parameter of the compiled functions (value 0 unless
given), so the compiled model is an ordinary closed one and its Jacobian w.r.t. that parameter is
the input column. An analysis point `P: analysis_point(a.y, b.u)` (Dyad's meaning) is the
connection `b.u = a.y`; as an input it becomes `b.u = a.y + P` (an additive perturbation, a new
parameter named P); opened, `b.u = P` (the connection removed, the input signal driven by P); as
an output it reads its output signal `a.y`.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import sympy

from compiler.errors import DyadError, suggest_name
from compiler.model.flat import INPUT, Equation, FlatSystem, Origin, Parameter


@dataclass(frozen=True)
class AnalysisPoint:
    name: str
    outputs: tuple[str, ...]       # the output signal's scalar names (a.y)
    inputs: tuple[str, ...]        # the input signal's scalar names (b.u)
    span: object = None

    def scalar_names(self) -> list[str]:
        """The names of its perturbations: P, or P[1], P[2], ... for an array signal."""
        if len(self.inputs) == 1:
            return [self.name]
        return [f"{self.name}[{k + 1}]" for k in range(len(self.inputs))]


def analysis_points(flat: FlatSystem) -> dict[str, AnalysisPoint]:
    found = flat.metadata.get("analysis_points") or {}
    return {name: AnalysisPoint(name, tuple(out), tuple(inp), span)
            for name, (out, inp, span) in found.items()}


def free_inputs(flat: FlatSystem) -> list[str]:
    return [v.name for v in flat.variables if v.kind == INPUT]


def analysis_point(flat: FlatSystem, name: str) -> AnalysisPoint:
    points = analysis_points(flat)
    if name not in points:
        listed = ", ".join(sorted(points)) or "none"
        close = suggest_name(name, points)
        raise DyadError(f"`{flat.name}` has no analysis point `{name}`" + (f"; {close}" if close else ""),
                        hint=f"its analysis points: {listed} (declared as `NAME: "
                             f"analysis_point(output_signal, input_signal)`)")
    return points[name]


def with_linear_inputs(flat: FlatSystem, perturbed: list[str] = (), opened: list[str] = ()
                       ) -> FlatSystem:
    """`flat` with every free top-level input a parameter (value 0), an additive perturbation
    parameter at each analysis point of `perturbed`, and the connection of each point of `opened`
    replaced by a parameter driving its input signal."""
    taken = {v.name for v in flat.variables} | {p.name for p in flat.parameters}
    equations = list(flat.equations)
    added: list[Parameter] = []
    for name in dict.fromkeys([*opened, *perturbed]):
        point = analysis_point(flat, name)
        for k, (out, inp, param) in enumerate(zip(point.outputs, point.inputs, point.scalar_names())):
            if param in taken:
                raise DyadError(f"analysis point `{name}` has the name of a variable or parameter of "
                                f"`{flat.name}`, so it cannot name an input", point.span)
            index = _connection_index(equations, out, inp)
            if index is None:
                raise DyadError(f"analysis point `{name}`: no connection `{inp} = {out}` found in "
                                f"the flat model (its output signal drives another set?)", point.span)
            old = equations[index]
            driven = sympy.Symbol(param) if name in opened else sympy.Symbol(out) + sympy.Symbol(param)
            equations[index] = Equation(sympy.Symbol(inp) - driven, old.origin, "analysis_point")
            added.append(Parameter(param, 0.0, origin=Origin("", point.span),
                                   description=f"perturbation at analysis point {name}"))
            taken.add(param)
    variables = [v for v in flat.variables if v.kind != INPUT]
    inputs = [Parameter(v.name, 0.0, units=v.units, description=v.description, origin=v.origin)
              for v in flat.variables if v.kind == INPUT]
    metadata = dict(flat.metadata)
    metadata["linear_inputs"] = [q.name for q in inputs + added]
    return dataclasses.replace(flat, variables=variables, equations=equations,
                               parameters=list(flat.parameters) + inputs + added, metadata=metadata)


def _connection_index(equations: list[Equation], out: str, inp: str) -> int | None:
    target = sympy.Symbol(inp) - sympy.Symbol(out)
    for i, equation in enumerate(equations):
        if equation.kind == "connect" and sympy.expand(equation.residual - target) == 0:
            return i
        if equation.kind == "connect" and sympy.expand(equation.residual + target) == 0:
            return i
    return None


def check_not_differentiated(flat: FlatSystem, analysis, inputs: list[str]) -> None:
    """An input that some derivative depends on (a differentiated variable set by it, or an
    equation with it that the index reduction differentiated) would need its own time derivative,
    which a parameter does not have (it is held constant): refuse, located, rather than give a
    linear model without those terms."""
    wanted = {sympy.Symbol(name) for name in inputs}
    differentiated = set(flat.derivatives.values())
    for name, expression in analysis.alias.eliminated.items():
        used = sorted(s.name for s in sympy.sympify(expression).free_symbols & wanted)
        if used and name in differentiated:
            raise _differentiated(flat, used[0], f"`{name}` follows it and is differentiated",
                                  flat.variable(name).origin.span)
    system = analysis.system
    for i, equation in enumerate(system.equations):
        used = sorted(s.name for s in equation.free_symbols & wanted)
        if used and system.eq_to_diff[i] >= 0:
            raise _differentiated(flat, used[0], "the index reduction differentiates an equation with it",
                                  getattr(system.origins[i], "span", None))


def _differentiated(flat: FlatSystem, name: str, why: str, span) -> DyadError:
    return DyadError(f"input `{name}` of `{flat.name}` would need its time derivative ({why}): dyadc "
                     f"holds inputs constant and cannot linearize from it", span,
                     hint="drive it through a filter or an integrator of its own (a state), or "
                          "linearize from another input")
