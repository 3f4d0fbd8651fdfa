"""Findings of the metamorphic generator (tests/metamorphic, issue 25), each pinned by a small
model of our own: the same physics written another way must give the same verdict and numbers."""
from __future__ import annotations

import math

import pytest

from compiler import api


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
