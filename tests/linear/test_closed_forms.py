"""Linearizations against closed forms (tests/models/Linear/, tests/models/Hard/).

Each model's (A, B, C, D) comes from CasADi Jacobians with the algebraic unknowns eliminated
(compiler/linear/elimination.py); the expected values are derived by hand from the equations.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import sympy

from compiler.linear.request import Request, closed_loop_function, linearize_spec

MODELS = (str(Path(__file__).resolve().parent.parent / "models"),)
G = 9.80665


def linearize(spec: str, **request) -> object:
    return linearize_spec(spec, Request(**request), lib_dirs=MODELS, cache=False)


def frequency_response(system, w: float) -> np.ndarray:
    s = 1j * w
    n = system.A.shape[0]
    return system.C @ np.linalg.solve(s * np.eye(n) - system.A, system.B) + system.D


def test_rc_low_pass_is_one_over_rcs_plus_one():
    system = linearize("Linear.RCLowPass", outputs=("vout",), params={"R": 200.0, "C": 5e-3})
    assert system.states == ["capacitor.v"] and system.inputs == ["V"] and system.outputs == ["vout"]
    rc = 200.0 * 5e-3
    for w in (0.1, 1.0, 30.0):
        assert frequency_response(system, w)[0, 0] == pytest.approx(1 / (rc * 1j * w + 1), rel=1e-13)
    assert system.dc_gain()[0, 0] == pytest.approx(1.0, rel=1e-14)


def test_mass_spring_damper_from_force_to_position():
    m, c, d = 2.0, 50.0, 3.0
    system = linearize("Linear.MassSpringDamper", outputs=("mass.s",))
    assert np.sort_complex(system.poles()) == pytest.approx(np.sort_complex(np.roots([m, d, c])), rel=1e-13)
    for w in (0.5, 5.0, 50.0):
        expected = 1 / (m * (1j * w) ** 2 + d * 1j * w + c)
        assert frequency_response(system, w)[0, 0] == pytest.approx(expected, rel=1e-12)


# DC motor (R, L, k, J, b) under a PI speed loop (Kp, Ki), tests/models/Linear/DCMotorPI.dyad:
# plant P = k / ((L s + R)(J s + b) + k^2), controller C = Kp + Ki / s, closed loop from r to w
# k (Kp s + Ki) / (L J s^3 + (L b + R J) s^2 + (R b + k^2 + k Kp) s + k Ki).
R, L, K, J, B, KP, KI = 2.0, 0.5, 0.1, 0.02, 0.2, 10.0, 50.0
CHARACTERISTIC = [L * J, L * B + R * J, R * B + K * K + K * KP, K * KI]


def plant(s):
    return K / ((L * s + R) * (J * s + B) + K * K)


def controller(s):
    return KP + KI / s


def test_dc_motor_pi_loop_closed_loop_poles_and_reference_response():
    system = linearize("Linear.DCMotorPI", outputs=("motor.w",))
    assert system.inputs == ["r"]
    assert np.sort_complex(system.poles()) == pytest.approx(np.sort_complex(np.roots(CHARACTERISTIC)), rel=1e-12)
    for w in (0.3, 3.0, 30.0):
        s = 1j * w
        expected = K * (KP * s + KI) / np.polyval(CHARACTERISTIC, s)
        assert frequency_response(system, w)[0, 0] == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("point", ["u", "y"])
def test_sensitivity_functions_at_analysis_points(point):
    sensitivity = closed_loop_function("Linear.DCMotorPI", "sensitivity", point, Request(), MODELS)
    complementary = closed_loop_function("Linear.DCMotorPI", "comp_sensitivity", point, Request(), MODELS)
    loop = closed_loop_function("Linear.DCMotorPI", "loop_transfer", point, Request(), MODELS)
    for w in (0.1, 1.0, 10.0, 100.0):
        s_, t_, l_ = (frequency_response(f, w)[0, 0] for f in (sensitivity, complementary, loop))
        assert abs(s_ + t_ - 1.0) < 1e-12
        expected_loop = controller(1j * w) * plant(1j * w)          # SISO: PC at either point
        assert l_ == pytest.approx(expected_loop, rel=1e-12)
        assert s_ == pytest.approx(1 / (1 + expected_loop), rel=1e-12)
    assert sensitivity.inputs == [point] and sensitivity.outputs == [point]


def test_plant_alone_between_analysis_points_with_the_loop_opened():
    system = linearize("Linear.DCMotorPI", inputs=("u",), outputs=("y",), opened=("u",))
    for w in (0.2, 2.0, 20.0):
        assert frequency_response(system, w)[0, 0] == pytest.approx(plant(1j * w), rel=1e-12)


def test_cartesian_pendulum_at_the_bottom_oscillates_through_the_index_reduction():
    system = linearize("Hard.CartesianPendulum", params={"theta0": 0.0})
    assert system.states == ["x", "u"]
    assert np.sort(system.poles().imag) == pytest.approx([-np.sqrt(G), np.sqrt(G)], rel=1e-13)
    assert np.abs(system.poles().real).max() < 1e-12


def test_cartesian_pendulum_at_the_top_is_a_saddle():
    system = linearize("Linear.PendulumTop")
    assert np.sort(system.poles().real) == pytest.approx([-np.sqrt(G), np.sqrt(G)], rel=1e-12)
    assert np.abs(system.poles().imag).max() < 1e-12


def test_switching_pendulum_is_linearized_in_the_state_set_active_at_the_point():
    """The large swing starts in the states (y, v) and passes to (x, u) near the bottom; at t = 0.6
    (x, u) is active. Reduced to x, u (lower branch, L = m = 1): u' = -x (u^2 / (1 - x^2) + g
    sqrt(1 - x^2)), whose Jacobian at the point is the expected A."""
    started = linearize("Hard.CartesianPendulumLarge")
    assert started.states == ["y", "v"]
    system = linearize("Hard.CartesianPendulumLarge", at=0.6)
    assert system.states == ["x", "u"]
    x, u = sympy.symbols("x u")
    acceleration = -x * (u ** 2 / (1 - x ** 2) + G * sympy.sqrt(1 - x ** 2))
    point = {x: system.state_values["x"], u: system.state_values["u"]}
    expected = np.array([[0.0, 1.0], [float(acceleration.diff(x).subs(point)),
                                       float(acceleration.diff(u).subs(point))]])
    assert system.A == pytest.approx(expected, rel=1e-7, abs=1e-9)
    assert system.time == pytest.approx(0.6)


def test_steady_state_of_the_mass_spring_damper_under_a_constant_force():
    system = linearize("Linear.MassSpringDamper", outputs=("mass.s",), steady=True, op={"F": 5.0})
    assert system.state_values["mass.s"] == pytest.approx(5.0 / 50.0, rel=1e-12)
    assert system.input_values == {"F": 5.0}
    assert system.steady_residual < 1e-12


def test_minimal_realization_drops_the_unobservable_mode():
    full = linearize("Linear.DCMotorPI", inputs=("u",), outputs=("y",), opened=("u",))
    minimal = linearize("Linear.DCMotorPI", inputs=("u",), outputs=("y",), opened=("u",), minimal=True)
    assert len(full.states) == 3 and len(minimal.states) == 2      # the opened integrator
    for w in (0.2, 2.0):
        assert frequency_response(minimal, w)[0, 0] == pytest.approx(plant(1j * w), rel=1e-9)


def test_from_the_cache_the_same_linear_model():
    """With the compiled model in the compilation cache, linearize reads it from there (no flat
    model, no compile) and gives the same matrices as a fresh compilation."""
    from compiler.cache import models
    from compiler.pipeline import compile_or_load
    compile_or_load("Hard.CartesianPendulum", MODELS)
    if models.load("Hard.CartesianPendulum", MODELS) is None:
        pytest.skip("the compilation cache is off (DYADC_CACHE_DIR=off)")
    cached = linearize_spec("Hard.CartesianPendulum", Request(outputs=("lambda", "y")), lib_dirs=MODELS)
    compiled = linearize("Hard.CartesianPendulum", outputs=("lambda", "y"))
    for key in "ABCD":
        assert np.array_equal(getattr(cached, key), getattr(compiled, key))
    assert cached.states == compiled.states and cached.outputs == ["lambda", "y"]
