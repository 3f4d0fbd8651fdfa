"""Under-determined initialization (issue 17 item 6): unknowns nobody fixes take their start
values / guesses (0 without one), states with a given value first, with a note; over-determined
but consistent initial conditions stay accepted, inconsistent ones fail naming the residuals."""
from __future__ import annotations

import math

import pytest

from compiler import api
from compiler.cli import main
from compiler.errors import DyadError

# Two first-order lags in series driven by a constant u = 1: x1' = (u - x1)/T1, x2' = (x1 - x2)/T2.
# RELATIONS is where each test puts its initial conditions; x2 has a guess of 0.25.
LAGS = """
component Lags
  parameter T1::Real = 0.5
  parameter T2::Real = 2
  variable x1::Real
  variable x2::Real(guess = 0.25)
  variable y::Real
relations
  RELATIONS
  der(x1) = (1 - x1) / T1
  der(x2) = (x1 - x2) / T2
  y = x1 + x2
end
"""


def _model(tmp_path, relations: str) -> str:
    path = tmp_path / "Lags.dyad"
    path.write_text(LAGS.replace("RELATIONS", relations))
    return str(path)


def _closed_form(t: float, x10: float, x20: float, T1: float = 0.5, T2: float = 2.0):
    """x1 = 1 + (x10 - 1) e^(-t/T1); x2 from the linear ODE driven by x1 (T1 != T2)."""
    a = x10 - 1.0
    x1 = 1.0 + a * math.exp(-t / T1)
    c = a * T1 / (T1 - T2)               # particular part of x2 for the e^(-t/T1) term of x1
    x2 = 1.0 + c * math.exp(-t / T1) + (x20 - 1.0 - c) * math.exp(-t / T2)
    return x1, x2


def test_free_states_take_their_guess_or_zero_and_the_run_follows_the_closed_form(tmp_path):
    compilation = api.compile(_model(tmp_path, ""))
    assert compilation.reduced.initial.chosen == {"x1": 0.0, "x2": 0.25}
    result = api.simulate_compiled(compilation, 3.0, rtol=1e-10, atol=1e-12, points=31)
    x1, x2 = _closed_form(3.0, 0.0, 0.25)
    assert result["x1"][-1] == pytest.approx(x1, rel=1e-7)
    assert result["x2"][-1] == pytest.approx(x2, rel=1e-7)


def test_a_given_initial_condition_is_kept_and_only_the_rest_is_chosen(tmp_path):
    compilation = api.compile(_model(tmp_path, "initial y = 2"))
    # y = x1 + x2 fixes one of the two: the state with a guess (x2) is preferred for the other
    assert compilation.reduced.initial.chosen == {"x2": 0.25}
    result = api.simulate_compiled(compilation, 1.0, rtol=1e-10, atol=1e-12, points=11)
    assert result["x1"][0] == pytest.approx(1.75, abs=1e-10)
    assert result["y"][0] == pytest.approx(2.0, abs=1e-10)


def test_a_determined_model_chooses_nothing(tmp_path):
    compilation = api.compile(_model(tmp_path, "initial x1 = 0.5\n  initial x2 = 0"))
    assert compilation.reduced.initial.chosen == {}


def test_over_determined_but_consistent_is_accepted(tmp_path):
    compilation = api.compile(_model(tmp_path, "initial x1 = 0.5\n  initial x2 = 0\n  initial y = 0.5"))
    assert compilation.reduced.initial.chosen == {}
    result = api.simulate_compiled(compilation, 1.0, rtol=1e-10, atol=1e-12, points=11)
    x1, x2 = _closed_form(1.0, 0.5, 0.0)
    assert (result["x1"][-1], result["x2"][-1]) == (pytest.approx(x1, rel=1e-7), pytest.approx(x2, rel=1e-7))


def test_over_determined_and_inconsistent_fails_naming_the_conditions(tmp_path):
    compilation = api.compile(_model(tmp_path, "initial x1 = 0.5\n  initial x2 = 0\n  initial y = 3"))
    with pytest.raises(DyadError) as caught:
        api.simulate_compiled(compilation, 1.0)
    assert "initialization failed" in caught.value.message


def test_simulate_prints_the_note_naming_the_chosen_values(tmp_path, capsys):
    assert main(["simulate", _model(tmp_path, "initial x1 = 0.5"), "--stop", "1"]) == 0
    err = capsys.readouterr().err
    assert "note: the initial conditions leave 1 unknown(s) free" in err and "x2 = 0.25" in err
