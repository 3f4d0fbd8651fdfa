"""dyadc's structural index against CasADi's own Pantelides (`casadi.dae_reduce_index`), for every
model of tests/structure/models/StructureModels.

The fully implicit DAE handed to CasADi is built from the FlatSystem alone: residuals in the
variables that have a derivative (x_impl), their derivative symbols (dx_impl) and the other
variables (z). Before that, every algebraic variable that an equation defines with a constant
coefficient (`z = f(...)`, `c * z + g(...) = 0`) is substituted away, with its equation. This is an
equivalence transformation that leaves the index alone, and it is needed: CasADi 3.8 computes the
index (`stats["index"] = max_order + 1`) and then fails in its post-processing (`complement()`
over `xs.size()` in integration_tools.cpp, "Some elements in v fall out of [0, size[") whenever a
variable of the z block or a newly created derivative is differentiated twice — which happens
in every Frame2D mechanism, where the frame positions are algebraic. Substitution leaves the
positions of the Body components (which have derivatives) to be differentiated instead.
"""
from __future__ import annotations

import casadi as ca
import pytest
import sympy

from compiler.model.flat import TIME, FlatSystem
from compiler.lower.to_casadi import SXLowering
from tests.structure.test_models import compiled


def substitute_defined_algebraics(flat: FlatSystem) -> tuple[list[sympy.Expr], set[str]]:
    """Residuals (parameters replaced by their values) with every algebraic variable that some
    equation solves with a nonzero constant coefficient eliminated; returns them and the names
    of the algebraic variables left."""
    differentiated = set(flat.derivatives.values())
    values = {sympy.Symbol(p.name): sympy.Float(p.value) for p in flat.parameters if p.value is not None}
    residuals = [e.residual.xreplace(values) for e in flat.equations]
    algebraic = {sympy.Symbol(v.name) for v in flat.variables if v.name not in differentiated}
    progress = True
    while progress:
        progress = False
        for i, residual in enumerate(residuals):
            for z in sorted(residual.free_symbols & algebraic, key=lambda s: s.name):
                coefficient = sympy.diff(residual, z)
                if coefficient.is_number and coefficient != 0:
                    definition = -residual.xreplace({z: 0}) / coefficient
                    residuals = [r.xreplace({z: definition}) for k, r in enumerate(residuals) if k != i]
                    algebraic.discard(z)
                    progress = True
                    break
            if progress:
                break
    return residuals, {z.name for z in algebraic}


def casadi_structural_index(flat: FlatSystem) -> int:
    residuals, algebraic = substitute_defined_algebraics(flat)
    present = {s.name for r in residuals for s in r.free_symbols}
    derivative_of = {v: d for d, v in flat.derivatives.items()}
    implicit = [v.name for v in flat.variables if v.name in derivative_of and derivative_of[v.name] in present]
    # a variable whose derivative cancelled out (e.g. `I * der(w) = tau` with I = 0) is algebraic now
    others = [v.name for v in flat.variables
              if v.name in present and (v.name in algebraic or (v.name in derivative_of and v.name not in implicit))]
    x = ca.SX.sym("x", len(implicit))
    dx = ca.SX.sym("dx", len(implicit))
    z = ca.SX.sym("z", len(others))
    t = ca.SX.sym("t")
    env = {name: x[i] for i, name in enumerate(implicit)}
    env.update({derivative_of[name]: dx[i] for i, name in enumerate(implicit)})
    env.update({name: z[i] for i, name in enumerate(others)})
    env[TIME.name] = t
    lowering = SXLowering(env, "CasADi index cross-check")
    alg = ca.vertcat(*[lowering.lower(r) for r in residuals])
    assert alg.numel() == len(implicit) + len(others), "the substituted system is not square"
    _, stats = ca.dae_reduce_index({"x_impl": x, "dx_impl": dx, "z": z, "alg": alg, "t": t}, {})
    return int(stats["index"])


def test_the_cross_check_sees_the_index_of_a_textbook_pendulum():
    # The check itself: CasADi must find index 3 for the plain Cartesian pendulum.
    assert casadi_structural_index(compiled("CartesianPendulum").flat) == 3


@pytest.mark.parametrize("name", ["CartesianPendulum", "CartesianPendulumHigh", "FramePendulum",
                                  "DoublePendulum", "SliderCrank", "FourBar"])
def test_dyadc_and_casadi_agree_on_the_index_of_mechanisms(name):
    compilation = compiled(name)
    assert compilation.report.structural_index == casadi_structural_index(compilation.flat) == 3


@pytest.mark.parametrize("name", ["CapacitorMirror", "TransistorAmplifier"])
def test_dyadc_and_casadi_agree_on_the_index_of_circuits(name):
    compilation = compiled(name)
    assert compilation.report.structural_index == casadi_structural_index(compilation.flat)


@pytest.mark.parametrize("name", ["CapacitorMirror", "TransistorAmplifier"])
def test_casadi_calls_the_circuits_index_1(name):
    # CasADi's Pantelides sees the structurally regular mass matrix; the numerically singular
    # one is dyadc's rank check's business. Both views agree the DAE is index 1.
    assert casadi_structural_index(compiled(name).flat) == 1
