"""A parameter value that makes the index-1 system singular (a mass of 0): the run can only fail at
its first step; the error names the equation and the parameter (issue 19 item 10)."""
from __future__ import annotations

import math
import textwrap
from pathlib import Path

import sympy

from compiler import api
from compiler.cli import main
from compiler.errors import Span
from compiler.model.flat import Origin
from compiler.structure.diagnostics import parameter_singularity_error
from compiler.structure.indexed import IndexedSystem

s, v, ds, dv, x = (sympy.Symbol(n) for n in ["s", "v", "der(s)", "der(v)", "x"])
m, m1, m2, c = (sympy.Symbol(n) for n in ["m", "m1", "m2", "c"])
HERE = Span("Model.dyad", 8, 3, 8, 17)


def oscillator(coefficient: sympy.Expr) -> IndexedSystem:
    """der(s) = v; coefficient*der(v) + c*s = 0, with the states s and v known at each step."""
    return IndexedSystem(names=["s", "v", "der(s)", "der(v)"], var_to_diff=[2, 3, -1, -1],
                         equations=[ds - v, coefficient * dv + c * s],
                         origins=[Origin("", None), Origin("mass", HERE)], eq_to_diff=[-1, -1])


STATES_KNOWN = [False, False, True, True]


def test_a_zero_mass_names_the_equation_and_the_parameter():
    err = parameter_singularity_error(oscillator(m), STATES_KNOWN, {"m": 0.0, "c": 1.0})
    assert err is not None and err.span == HERE
    assert "with `m` = 0" in err.message and "no longer contains `der(v)`" in err.message
    assert "`m`" in err.hint and "-p m=" in err.hint


def test_a_nonzero_mass_is_fine():
    assert parameter_singularity_error(oscillator(m), STATES_KNOWN, {"m": 1e-9, "c": 1.0}) is None


def test_a_coefficient_that_cancels_names_every_parameter_in_it():
    err = parameter_singularity_error(oscillator(m1 - m2), STATES_KNOWN,
                                      {"m1": 2.0, "m2": 2.0, "c": 1.0})
    assert err is not None and "`m1` = 2, `m2` = 2" in err.message
    assert parameter_singularity_error(oscillator(m1 - m2), STATES_KNOWN,
                                       {"m1": 2.0, "m2": 1.0, "c": 1.0}) is None


def test_a_coefficient_in_the_unknowns_is_never_blamed():
    """Only parameters are substituted: x*der(v) may vanish somewhere, but not identically."""
    system = IndexedSystem(names=["s", "v", "x", "der(s)", "der(v)"], var_to_diff=[3, 4, -1, -1, -1],
                           equations=[ds - v, x * dv + c * s, x - 1 - m * 0],
                           origins=[Origin("")] * 3, eq_to_diff=[-1, -1, -1])
    assert parameter_singularity_error(system, [False, False, True, True, True],
                                       {"m": 0.0, "c": 1.0}) is None


def test_another_equation_can_still_determine_the_lost_unknown():
    """m*der(v) vanishes, but a second equation also determines der(v): not singular."""
    system = IndexedSystem(names=["s", "v", "w", "der(s)", "der(v)"], var_to_diff=[3, 4, -1, -1, -1],
                           equations=[ds - v, m * dv + c * s - sympy.Symbol("w"), dv + s],
                           origins=[Origin("")] * 3, eq_to_diff=[-1, -1, -1])
    assert parameter_singularity_error(system, [False, False, True, True, True],
                                       {"m": 0.0, "c": 1.0}) is None


MODEL = """
connector Flange
  potential s::Real
  flow f::Real
end
component Mass
  flange = Flange()
  parameter m::Real = 1
  variable s::Real
  variable v::Real
relations
  s = flange.s
  der(s) = v
  m*der(v) = flange.f
end
component Anchor
  flange = Flange()
relations
  flange.s = 0
end
component Spring
  a = Flange()
  b = Flange()
  parameter c::Real = 1
relations
  a.f = c*(a.s - b.s)
  a.f + b.f = 0
end
component Oscillator
  body = Mass(m = 0, s(initial = 1), v(initial = 0))
  spring = Spring()
  anchor = Anchor()
relations
  connect(anchor.flange, spring.a)
  connect(spring.b, body.flange)
end
"""


def test_a_zero_mass_in_a_component_is_located_and_an_override_runs(tmp_path: Path, capsys):
    path = tmp_path / "Oscillator.dyad"
    path.write_text(textwrap.dedent(MODEL).lstrip("\n"), encoding="utf-8")
    code = main(["simulate", str(path), "--stop", "1"])
    err = capsys.readouterr().err
    assert code == 1 and "Traceback" not in err
    line = next(i + 1 for i, text in enumerate(path.read_text().splitlines()) if "m*der(v)" in text)
    # (IDAS itself may print a line to stderr before it)
    assert f"\n{path}:{line}:3: error: the model is singular at the start: with `body.m` = 0" \
        in "\n" + err, err
    assert "m*der(v) = flange.f" in err and "-p body.m=" in err
    result = api.simulate(str(path), 2.0, params={"body.m": 4.0}, rtol=1e-8, atol=1e-10)
    assert abs(result["body.s"][-1] - math.cos(2.0 / 2.0)) < 1e-6     # omega = sqrt(c/m) = 1/2
