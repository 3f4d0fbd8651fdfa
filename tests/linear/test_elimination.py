"""compiler/linear/elimination.py alone, on the Cartesian pendulum (tests/models/Hard/
CartesianPendulum.dyad, L = m = 1) in its states (x, u) at a point that is not an equilibrium,
with the gravity g taken as the input. By hand, on the lower branch: y = -sqrt(1 - x^2),
v = -x u / y, lambda = u^2 + v^2 - g y, der(u) = -lambda x, so d der(u) / d g = x y; the
algebraic unknowns y and lambda come out of Newton's method on the index-1 system."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import sympy

from compiler import api
from compiler.linear.elimination import EliminatedSystem

MODELS = (str(Path(__file__).resolve().parent.parent / "models"),)


def test_values_and_jacobians_at_states_inputs_parameters_time():
    model = api.compile("Hard.CartesianPendulum", lib_dirs=MODELS).model
    assert model.state_names == ["x", "u"] and model.algebraic_names == ["y", "lambda"]
    system = EliminatedSystem(model, [model.parameter_names.index("g")], ["lambda", "y"])
    x0, u0, g0 = 0.3, 0.5, 9.0
    found = system.evaluate(x=[x0, u0], u=[g0], p=model.parameter_vector(), t=0.0, z_guess=[-0.9, 9.0])

    x, u, g = sympy.symbols("x u g")
    y = -sympy.sqrt(1 - x ** 2)
    lam = u ** 2 + (x * u / y) ** 2 - g * y
    point = {x: x0, u: u0, g: g0}
    value = lambda e: float(e.subs(point))  # noqa: E731
    assert found.z == pytest.approx([value(y), value(lam)], rel=1e-13)
    assert found.derivatives == pytest.approx([u0, value(-lam * x)], rel=1e-13)
    assert found.outputs == pytest.approx([value(lam), value(y)], rel=1e-13)
    acceleration = -lam * x
    assert found.A == pytest.approx(np.array([[0.0, 1.0], [value(acceleration.diff(x)),
                                                           value(acceleration.diff(u))]]), rel=1e-12)
    assert found.B == pytest.approx(np.array([[0.0], [value(x * y)]]), rel=1e-13)
    assert found.C == pytest.approx(np.array([[value(lam.diff(x)), value(lam.diff(u))],
                                              [value(y.diff(x)), 0.0]]), rel=1e-12, abs=1e-15)
    assert found.D == pytest.approx(np.array([[value(-y)], [0.0]]), rel=1e-13)
