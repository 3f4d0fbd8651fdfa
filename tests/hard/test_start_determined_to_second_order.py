"""Initial conditions that fix a coordinate at its extremum determine the others only to second
order: the pendulum's bob given by its height at the bottom (`initial y = -L`) leaves x in
x^2 = 0, a double root the initialization finds only to about the square root of its tolerance,
and Andrews' squeezer given by a dependent angle at its extremum stopped 7e-6 off in the crank
angle, after which IDAS failed at t = 0 (metamorphic start moves, issue 25). Such a start is a
located error naming the coordinate and the equations, never a run from a point that is off."""
from __future__ import annotations

from pathlib import Path

import pytest

from compiler import api
from compiler.errors import DyadError

PENDULUM = Path(__file__).resolve().parents[1] / "models" / "Hard" / "CartesianPendulum.dyad"


def test_a_pendulum_given_by_its_height_at_the_bottom_is_a_located_error(tmp_path):
    source = PENDULUM.read_text()
    assert source.count("  initial x = L * sin(theta0)\n") == 1
    path = tmp_path / PENDULUM.name
    path.write_text(source.replace("  initial x = L * sin(theta0)\n", "  initial y = -L\n"))
    with pytest.raises(DyadError) as caught:
        api.simulate(str(path), 1.0)
    message = caught.value.format()
    assert "the initial conditions determine x only to second order or not at all" in message, message
    line = source.splitlines().index("  initial x = L * sin(theta0)") + 1
    assert f"{path}:{line}:3: note: this initial condition" in message, message
    assert "x ^ 2 + y ^ 2 = L ^ 2" in message, message


def test_the_same_pendulum_given_by_its_horizontal_position_runs(tmp_path):
    path = tmp_path / PENDULUM.name
    path.write_text(PENDULUM.read_text().replace("  initial x = L * sin(theta0)\n", "  initial x = 0\n"))
    result = api.simulate(str(path), 1.0, rtol=1e-8, atol=1e-8)
    assert result["y"][0] == pytest.approx(-1.0, abs=1e-12)
    assert max(abs(result["x"])) < 1e-12           # at rest at the bottom: it stays there
