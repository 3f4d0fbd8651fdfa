"""A failed run is blamed on a vanishing factor only where the solve divides by it: the factor of
the unknown an equation is solved for alone (an assignment, a one-unknown algebraic residual).
An off-diagonal entry of a mass matrix that passes through 0 makes nothing singular; naming it
sent the reader of Andrews' squeezer's failure at rtol 1e-11 after the wrong equation."""
from __future__ import annotations

import math
import re

import pytest

from compiler import api
from compiler.errors import DyadError, SimulationError
from compiler.run_checks import run_parameter_values
from compiler.model.run_failures import _candidates, _solved_for, diagnose

# two coupled bodies: the mass matrix [[m1, c cos(th)], [c cos(th), m2]] stays regular
# (m1 m2 > c^2) while its off-diagonal entry passes through 0 at th = pi / 2
COUPLED = """component Coupled
  parameter m1::Real = 2.0
  parameter m2::Real = 1.0
  parameter c::Real = 0.5
  parameter w::Real = 1.0
  variable th::Real(initial = 0.0)
  variable x::Real(initial = 1.0)
  variable v::Real(initial = 0.0)
  variable y::Real(initial = 0.0)
  variable u::Real(initial = 0.0)
relations
  der(th) = w
  der(x) = v
  der(y) = u
  MASS * der(v) + c * cos(th) * der(u) = -x
  c * cos(th) * der(v) + m2 * der(u) = -y
end
"""


def compiled(tmp_path, mass: str = "m1"):
    path = tmp_path / "Coupled.dyad"
    path.write_text(COUPLED.replace("MASS", mass), encoding="utf-8")
    return api.compile(str(path))


def coefficient_operands(compilation) -> list[str]:
    candidates = _candidates(compilation.flat, set(compilation.reduced.states),
                             _solved_for(compilation.reduced))
    return sorted(str(c.operand) for c in candidates if c.kind in ("coefficient", "jacobian"))


def test_an_off_diagonal_mass_entry_is_no_candidate_a_pivot_is(tmp_path):
    # the equations are solved for der(v) and der(u) (one torn, one residual alone): their
    # factors m1 and m2 are pivots, c * cos(th) is not
    assert coefficient_operands(compiled(tmp_path)) == ["m1", "m2"]
    assert coefficient_operands(compiled(tmp_path, "(m1 - time)")) == ["m1 - time", "m2"]


def test_a_failure_where_the_off_diagonal_entry_reaches_zero_keeps_the_solvers_words(tmp_path):
    # at the parent commit: "the factor `c*cos(th)` of `der(u)` in this equation reaches 0, so
    # nothing determines der(u) any more"
    compilation = compiled(tmp_path)
    t_fail = math.pi / 2 - 1e-4          # cos(th) = 1e-4 and falling
    error = SimulationError(f"simulation of Coupled failed at t = {t_fail}: IDA_CONV_FAIL",
                            t_fail, "IDA_CONV_FAIL")
    assert diagnose(error, compilation, run_parameter_values(compilation, None), 0.0) is error


def test_a_vanishing_pivot_is_still_named(tmp_path):
    # uncoupled (c = 0), the equation solved for der(v) divides by m1 - time, 0 at t = 2
    compiled(tmp_path, "(m1 - time)")
    with pytest.raises(DyadError) as caught:
        api.simulate(str(tmp_path / "Coupled.dyad"), 3.0, params={"c": 0.0})
    message = caught.value.format()
    assert re.match(rf"{re.escape(str(tmp_path / 'Coupled.dyad'))}:15:3: error: simulation of Coupled "
                    r"failed at t = (?:1\.99\d+|2): the factor `m1 - time` of `der\(v\)` in this "
                    r"equation reaches 0", message), message


def test_a_mass_matrix_that_degenerates_is_named_by_its_vanishing_pivot(tmp_path):
    # coupled (c = 0.5), the mass matrix [[m1 - time, c cos(th)], [c cos(th), m2]] is singular
    # where (m1 - time) m2 = c^2 cos(th)^2, before m1 - time itself reaches 0: the pivot that
    # vanishes is a Schur complement (in no flat equation); the block is named by all its unknowns:
    # der(v), the one IDAS solves for, and der(u), assigned from it inside the block
    compiled(tmp_path, "(m1 - time)")
    with pytest.raises(DyadError) as caught:
        api.simulate(str(tmp_path / "Coupled.dyad"), 3.0)
    lo, hi = 1.5, 2.0                   # bisection on (2 - t) - 0.25 cos(t)^2
    for _ in range(60):
        middle = 0.5 * (lo + hi)
        lo, hi = (middle, hi) if (2 - middle) - 0.25 * math.cos(middle) ** 2 > 0 else (lo, middle)
    assert caught.value.time_reached == pytest.approx(lo, abs=1e-3)
    message = caught.value.format()
    assert "the equations solved together for der(v) and der(u) become singular: the smallest singular value " \
           "of their Jacobian reaches 0" in message, message
    assert "IDA_" in message.split("note: the solver reported:")[1]


def test_a_block_is_named_by_its_torn_unknown_and_the_assignments_on_its_cycle(tmp_path):
    from compiler.model.singular_blocks import block_unknowns
    reduced = compiled(tmp_path, "(m1 - time)").reduced
    assert reduced.algebraics == ["der(v)"]
    assert block_unknowns(reduced, ["der(v)"], [0]) == ["der(v)", "der(u)"]
    outside = [a.target for a in reduced.assignments if a.target != "der(u)"]
    assert not set(outside) & set(block_unknowns(reduced, ["der(v)"], [0]))
