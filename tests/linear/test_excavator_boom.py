"""The excavator's boom axis at its working point (static equilibrium at the first waypoint),
from the boom position reference (analysis point `s_boom`, tests/models/Linear/ExcavatorBoomPoint.dyad)
to the boom joint angle and the cylinder stroke, against a finite difference of two simulations:
a small step eps of the reference held for h seconds. The linear prediction of that step is
C (integral_0^h e^{A s} ds) B + D (one matrix exponential of [[A, B], [0, 0]])."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

from compiler.api import simulate_compiled
from compiler.linear.operating_point import initial_point
from compiler.linear.request import Request, compile_linear
from compiler.linear.system import linearize_at

MODELS = (str(Path(__file__).resolve().parent.parent / "models"),)
OUTPUTS = ["boom_joint.phi", "boom_cyl.cylinder.s"]


def test_boom_axis_matches_a_finite_difference_of_a_small_simulated_step():
    compiled = compile_linear("Linear.ExcavatorBoomPoint", Request(inputs=("s_boom",)), MODELS, cache=False)
    model = compiled.compilation.model
    system = linearize_at(initial_point(model, model.parameter_vector()), ["s_boom"], OUTPUTS)
    assert system.states[:2] == ["boom_joint.phi", "boom_joint.w"]
    h, eps = 0.05, 1e-4
    runs = [simulate_compiled(compiled.compilation, h, points=2, rtol=1e-11, atol=1e-11,
                              params={"s_boom": value}) for value in (0.0, eps)]
    finite_difference = np.array([(runs[1][n][-1] - runs[0][n][-1]) / eps for n in OUTPUTS])
    n = len(system.states)
    augmented = np.zeros((n + 1, n + 1))
    augmented[:n, :n], augmented[:n, n:] = system.A, system.B
    predicted = (system.C @ scipy.linalg.expm(augmented * h)[:n, n:] + system.D).ravel()
    assert abs(predicted[0]) > 0.1                  # the step moves the boom
    assert predicted == pytest.approx(finite_difference, rel=1e-3)
