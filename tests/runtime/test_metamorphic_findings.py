"""Findings of the metamorphic generator (tests/metamorphic, issue 25), each pinned by a small
model of our own: the same physics written another way must give the same verdict and numbers."""
from __future__ import annotations

import math

import numpy as np
import pytest

from compiler import api
from compiler.errors import DyadError


def _model(tmp_path, name: str, body: str) -> str:
    path = tmp_path / f"{name}.dyad"
    path.write_text(f"component {name}\n{body}\nend\n", encoding="utf-8")
    return str(path)


def test_an_auxiliary_without_a_guess_under_a_square_root_initializes(tmp_path):
    """`r2` starts at 0, where d sqrt(r2) / d r2 is infinite: the initialization moves off the
    singularity (through `r2 = x^2 + y^2`) instead of stopping with numpy's internal
    'SVD did not converge'."""
    spec = _model(tmp_path, "Rod", """
  variable x::Real(guess = 1.0)
  variable y::Real
  variable vy::Real
  variable r2::Real
relations
  initial y = 0.6
  der(y) = vy
  der(vy) = -1.0
  sqrt(r2) = 1.0
  r2 = x ^ 2 + y ^ 2""")
    result = api.simulate(spec, 0.2, rtol=1e-10, atol=1e-12, points=3)
    assert result["x"][0] == pytest.approx(0.8, rel=1e-9)
    assert result["r2"][0] == pytest.approx(1.0, rel=1e-9)
    assert result["y"][-1] == pytest.approx(0.6 - 0.5 * 0.2 ** 2, rel=1e-9)


@pytest.mark.parametrize("written", ["x = 1.2", "1.2 = x", "x - 1.2 = 0", "0 = 0.0 - (1.2 - x)",
                                     "2 * x = 2 * h"])
def test_an_initial_equation_gives_its_start_value_on_either_side(tmp_path, written):
    """The start of `x` comes from the initial equation however it is written; from 0 the
    sqrt(x - 1) of the model has no derivative, and every form but `x = 1.2` failed before."""
    spec = _model(tmp_path, "Lift", f"""
  parameter h::Real = 1.2
  variable x::Real
  variable s::Real
relations
  initial {written}
  der(x) = 0.5
  s = sqrt(x - 1)""")
    start = {v.name: v.start for v in api.flatten(spec).variables}
    assert start["x"] == pytest.approx(1.2, rel=1e-15)
    result = api.simulate(spec, 1.0, rtol=1e-10, atol=1e-12, points=2)
    assert result["s"][-1] == pytest.approx(math.sqrt(0.7), rel=1e-8)


@pytest.mark.parametrize("height", ["y", "a"])
def test_the_state_choice_at_the_start_does_not_depend_on_a_name(tmp_path, height):
    """A pendulum released with its rod horizontal, its height without a start value: the
    choice at the start pivots on the Jacobian at the point the initialization starts from (0
    for the height), so `y` and `a` (sorting after and before `x`) choose the same states. By
    names alone, `a` made x the state where d(rod)/d(height) = 0 and the run failed at t = 0."""
    spec = _model(tmp_path, "Swing", f"""
  variable x::Real(guess = 1.0)
  variable {height}::Real
  variable vx::Real
  variable vy::Real
  variable lambda::Real
relations
  initial vy = 0
  initial x = 1.0
  der(x) = vx
  der({height}) = vy
  der(vx) = -lambda * x
  der(vy) = -lambda * {height} - 9.81
  x ^ 2 + {height} ^ 2 = 1.0""")
    compilation = api.compile(spec)
    assert compilation.model.state_names == [height, "vy"]
    result = api.simulate_compiled(compilation, 1.0, rtol=1e-8, atol=1e-8, points=3)
    # the angle ODE theta'' = -g sin(theta) from theta = pi/2, by RK4 (h = 5e-6): y(1) = -cos(theta)
    assert result[height][-1] == pytest.approx(-0.1650108, abs=1e-6)


def test_a_second_derivative_written_inline_keeps_the_state_set_watched(tmp_path):
    """`der(der(x))` in the model differentiates x as `der(x) = vx` does: x competes with y for
    the state set on equal terms, the choice is watched, and the run switches at the bottom of
    the swing. Counted as never differentiated, x lost every tie, nothing was watched and IDAS
    stopped at t = 0.592 (where y can no longer be a state)."""
    spec = _model(tmp_path, "Swing", """
  variable x::Real(guess = 1.0)
  variable y::Real
  variable vy::Real
  variable lambda::Real(guess = 0.0)
relations
  initial y = 0
  initial vy = 0
  der(y) = vy
  der(der(x)) = -lambda * x
  der(vy) = -lambda * y - 9.81
  x ^ 2 + y ^ 2 = 1.0""")
    compilation = api.compile(spec)
    (watched,) = compilation.model.state_sets
    assert watched["candidates"] == ["der(der(x))", "der(der(y))"]
    assert list(compilation.model.variants) == [frozenset({"der(y)", "der(vy)", "der(der(y))"})]
    result = api.simulate_compiled(compilation, 1.0, rtol=1e-8, atol=1e-8, points=3)
    # the angle ODE theta'' = -g sin(theta) from theta = pi/2, by RK4 (h = 5e-6): y(1) = -cos(theta)
    assert result["y"][-1] == pytest.approx(-0.1650108, abs=1e-6)


# Starts given on a derivative (issue 25): the initial system is judged as Modelica tools judge
# it, by its structure. Conditions that fix the same unknown twice are accepted when consistent
# (least squares) and named when not; an unknown no condition fixes starts at its start value
# (docs/structure.md). A condition that fixes a coordinate only to second order (a double root:
# the rod-horizontal pendulum above, `initial x = 1` with x^2 + y^2 = 1) is structurally regular
# and accepted; the generator does not make such moves (tests/metamorphic/agreement.py,
# KEPT_CONDITIONING), since the double root's direction is found only to about the square root
# of the initialization's residual tolerance.
OSCILLATOR = """
  variable x::Real
  variable v::Real
relations
  {first}
  {second}
  der(x) = v
  der(v) = -x"""


def test_a_rate_given_twice_is_accepted_when_consistent_and_the_position_starts_at_its_start(tmp_path):
    """`initial der(x) = 0` beside `initial v = 0` with der(x) = v: both fix v, none fixes x."""
    compilation = api.compile(_model(tmp_path, "Twice", OSCILLATOR.format(first="initial der(x) = 0",
                                                                          second="initial v = 0")))
    assert compilation.reduced.initial.chosen == {"x": 0.0}
    result = api.simulate_compiled(compilation, 1.0, rtol=1e-10, atol=1e-10, points=3)
    assert max(abs(result["x"])) == 0.0 and max(abs(result["v"])) == 0.0


def test_a_rate_given_twice_inconsistently_names_both_conditions(tmp_path):
    spec = _model(tmp_path, "Twice", OSCILLATOR.format(first="initial der(x) = 1", second="initial v = 0"))
    with pytest.raises(DyadError) as caught:
        api.simulate(spec, 1.0)
    message = caught.value.format()
    assert message.startswith("error: initialization failed at t = 0: the initial conditions are inconsistent")
    assert f"{spec}:6:3: note: this initial condition (<model>) is off by -0.5" in message, message
    assert f"{spec}:7:3: note: this initial condition (<model>) is off by 0.5" in message, message


def test_an_acceleration_given_in_place_of_the_position_starts_where_the_position_would(tmp_path):
    """`initial der(v) = -1` with der(v) = -x fixes x = 1 to first order: the same run as `initial x = 1`."""
    runs = [api.simulate(_model(tmp_path, name, OSCILLATOR.format(first=first, second="initial v = 0")),
                         1.0, rtol=1e-10, atol=1e-10, points=3) for name, first in
            (("Acceleration", "initial der(v) = -1"), ("Position", "initial x = 1"))]
    assert runs[0]["x"][0] == 1.0
    np.testing.assert_array_equal(runs[0]["x"], runs[1]["x"])
    assert runs[0]["x"][-1] == pytest.approx(math.cos(1.0), rel=1e-8)


def test_a_start_fixed_only_to_second_order_runs_with_the_double_root_found_to_the_square_root(tmp_path):
    """The rod horizontal (`initial x = 1`, x^2 + y^2 = 1): y^2 = 0 from y's guess -0.9, Newton
    converges linearly and stops with y at 5.3e-8 (residual 7e-16), x at 1 to 1.4e-15."""
    spec = _model(tmp_path, "Horizontal", """
  variable x::Real
  variable y::Real(guess = -0.9)
  variable vx::Real
  variable vy::Real
  variable lambda::Real
relations
  initial x = 1.0
  initial vx = 0
  der(x) = vx
  der(y) = vy
  der(vx) = -lambda * x
  der(vy) = -lambda * y - 9.81
  x ^ 2 + y ^ 2 = 1.0""")
    result = api.simulate(spec, 0.01, rtol=1e-8, atol=1e-8, points=2)
    assert 1e-9 < abs(result["y"][0]) < 1e-7
    assert result["x"][0] == pytest.approx(1.0, abs=1e-14)
