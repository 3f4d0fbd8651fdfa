"""Time and state events against closed forms: the driver stops exactly at every time where an
input is non-smooth and locates every state-dependent switch, whatever the output grid."""
from __future__ import annotations

import math
import os

import numpy as np
import pytest

from compiler import api

pytestmark = pytest.mark.usefixtures("each_codegen")     # C and the VM alike


def model_file(tmp_path, name: str, body: str) -> str:
    path = tmp_path / f"{name}.dyad"
    path.write_text(f"component {name}\n{body}\nend\n", encoding="utf-8")
    return str(path)


def test_a_step_at_five_seconds_into_a_first_order_lag(tmp_path):
    spec = model_file(tmp_path, "Lag", """
  parameter tau::Real = 0.7
  parameter t_step::Real = 5.0
  variable y::Real
relations
  initial y = 0
  tau * der(y) = (if time >= t_step then 1.0 else 0.0) - y""")
    result = api.simulate(spec, 10.0, rtol=1e-8, atol=1e-10, points=3)      # 0, 5, 10: coarse
    assert result.stats["codegen"] == os.environ["DYADC_CODEGEN"]
    exact = 1 - math.exp(-(10.0 - 5.0) / 0.7)
    assert result["y"][-1] == pytest.approx(exact, abs=1e-8)
    assert result["y"][1] == pytest.approx(0.0, abs=1e-12)
    moved = api.simulate(spec, 10.0, rtol=1e-8, atol=1e-10, points=3, params={"t_step": 2.5})
    assert moved["y"][-1] == pytest.approx(1 - math.exp(-7.5 / 0.7), abs=1e-8)


def test_a_short_pulse_after_a_long_constant_phase_is_not_stepped_over(tmp_path):
    spec = model_file(tmp_path, "LatePulse", """
  parameter t_on::Real = 900.0
  parameter width::Real = 0.28
  variable y::Real
relations
  initial y = 750
  der(y) = if time >= t_on and time < t_on + width then 1.0 else 0.0""")
    result = api.simulate(spec, 1000.0, rtol=1e-6, atol=1e-6, points=2)
    assert result["y"][-1] == pytest.approx(750.28, abs=1e-6)


def test_a_one_kilohertz_square_wave_into_an_rc_filter(tmp_path):
    spec = model_file(tmp_path, "SquareRC", """
  parameter f::Real = 1000.0
  parameter RC::Real = 2e-4
  variable v::Real
relations
  initial v = 0
  RC * der(v) = (if f * time - floor(f * time) < 0.5 then 1.0 else 0.0) - v""")
    result = api.simulate(spec, 1.0, rtol=1e-8, atol=1e-10, points=11)
    # closed form: each half period relaxes v towards 1 or 0 by the factor a = exp(-T/2 / RC)
    a = math.exp(-0.5e-3 / 2e-4)
    v = 0.0
    for _ in range(1000):
        v = 1 - (1 - v) * a           # high half
        v = v * a                     # low half
    assert result["v"][-1] == pytest.approx(v, abs=1e-7)
    assert result.stats["segments"] >= 2000


def test_a_tank_drains_until_it_is_empty_and_stays_empty(tmp_path):
    spec = model_file(tmp_path, "Tank", """
  parameter A::Real = 2.0
  parameter q::Real = 0.5
  variable h::Real
relations
  initial h = 1.0
  der(h) = if h > 0 then -q / A else 0""")
    result = api.simulate(spec, 10.0, rtol=1e-8, atol=1e-10, points=11)
    empty = 1.0 * 2.0 / 0.5
    times = [e["time"] for e in result.events]
    assert len(times) == 1 and times[0] == pytest.approx(empty, abs=1e-8)
    assert result["h"].min() > -1e-10                       # below zero only by the tolerance
    np.testing.assert_allclose(result["h"], np.maximum(1.0 - 0.25 * result.time, 0.0), atol=1e-9)


def test_a_saturated_controller_leaves_its_limit_when_the_closed_form_says(tmp_path):
    spec = model_file(tmp_path, "Saturated", """
  parameter tau::Real = 1.0
  parameter K::Real = 20.0
  parameter u_max::Real = 2.0
  parameter r::Real = 1.0
  variable y::Real
  variable u::Real
relations
  initial y = 0
  u = min(max(K * (r - y), -u_max), u_max)
  tau * der(y) = u - y""")
    result = api.simulate(spec, 3.0, rtol=1e-8, atol=1e-10, points=4)
    # saturated: y = u_max (1 - exp(-t / tau)) until K (r - y) = u_max
    leaves = -1.0 * math.log(1 - (1.0 - 2.0 / 20.0) / 2.0)
    first = min(e["time"] for e in result.events)
    # located to the state's own error: y is off by ~1e-8 at rtol 1e-8 and dy/dt ~ 1.1
    assert first == pytest.approx(leaves, abs=3e-8)


def test_a_bound_crossed_between_output_points_stops_the_run_where_it_is_crossed(tmp_path):
    from compiler import runtime
    from compiler.compiled_runs import model_on_its_code
    from compiler.lower.to_casadi import lower
    from tests.runtime.runtime_systems import draining
    # on the code and integrator this module's each_codegen asks for (a direct call makes the choice too)
    model = model_on_its_code(lower(draining()))
    with pytest.raises(runtime.SimulationFailed) as failure:
        runtime.simulate(model, 3.0, points=2, rtol=1e-8, atol=1e-10, bounds="error")   # outputs at 0, 3
    assert failure.value.variable == "x"
    assert failure.value.time_reached == pytest.approx(1.0, abs=1e-9)    # bound slack: atol
    assert "outside its declared min = 0" in str(failure.value)


def test_a_bound_left_is_warned_of_once_where_it_is_crossed_and_the_run_goes_on(tmp_path):
    from compiler import runtime
    from compiler.compiled_runs import model_on_its_code
    from compiler.lower.to_casadi import lower
    from compiler.runtime.checks import BoundWarning
    from tests.runtime.runtime_systems import draining
    # on the code and integrator this module's each_codegen asks for (a direct call makes the choice too)
    model = model_on_its_code(lower(draining()))
    with pytest.warns(BoundWarning) as caught:
        result = runtime.simulate(model, 3.0, points=2, rtol=1e-8, atol=1e-10)
    assert len(caught) == 1 and "left its declared min = 0" in str(caught[0].message)
    (left,) = result.stats["bounds_left"]
    assert left["variable"] == "x" and left["bound"] == "min" and left["time"] == pytest.approx(1.0, abs=1e-9)
    assert result.time[-1] == 3.0 and result["x"][-1] == pytest.approx(-2.0, abs=1e-8)


def test_a_condition_on_julias_rem_of_time_is_located_not_stepped_over(tmp_path, each_codegen):
    # `%` is Julia's rem (with the sign of its argument): no closed form for its times here, so the
    # driver watches the condition and locates each crossing: up through 1 at t = 1, 3, down (rem
    # jumps back to 0) at t = 2, 4. At the stop, t = 5, rem reaches 1 and the run ends: no
    # crossing (the native driver's IDAS reported a root at its tstop there, issue 32)
    spec = model_file(tmp_path, "HalfOn", """
  variable x::Real
relations
  initial x = 0
  der(x) = if time % 2.0 < 1.0 then 1.0 else 0.0""")
    result = api.simulate(spec, 5.0, rtol=1e-8, atol=1e-10, points=6)
    np.testing.assert_allclose(result["x"], [0, 1, 1, 2, 2, 3], atol=1e-7)
    located = [(round(e["time"], 6), e["direction"]) for e in result.events if "<" in e["event"]]
    assert located == [(1.0, "rising"), (2.0, "falling"), (3.0, "rising"), (4.0, "falling")]


def test_the_floor_inside_rem_jumps_where_rem_flips(tmp_path):
    """floor(0.5 |t|) (rem's quotient) jumps at t = 2 and 4, the instants rem's relation flips:
    both rows are listed there, in row order (CasADi's sampled path listed only the relation: it
    located one row per check interval, and the other had crossed by the located point)."""
    spec = model_file(tmp_path, "HalfOn", """
  variable x::Real
relations
  initial x = 0
  der(x) = if time % 2.0 < 1.0 then 1.0 else 0.0""")
    result = api.simulate(spec, 5.0, rtol=1e-8, atol=1e-10, points=6)
    listed = [(round(e["time"], 6), e["event"].split("(")[0], e["direction"]) for e in result.events]
    assert listed == [(0.0, "floor", "rising"), (1.0, "time - 2.0*floor", "rising"),
                      (2.0, "time - 2.0*floor", "falling"), (2.0, "floor", "falling"),
                      (3.0, "time - 2.0*floor", "rising"), (4.0, "time - 2.0*floor", "falling"),
                      (4.0, "floor", "rising")]


def test_two_relations_crossing_between_the_same_checks_are_both_listed(tmp_path):
    """`x < 0.302` crosses 0.1 ms before `x > 0.3021`, the first watched row, between the same two
    check times of CasADi's sampled path: the earlier is located first and both are listed once,
    and b switches at its own crossing (it switched at the later one's, unlisted, issue 32)."""
    spec = model_file(tmp_path, "Two", """
  variable x::Real
  variable a::Real
  variable b::Real
relations
  initial x = 0
  initial a = 0
  initial b = 0
  der(x) = 1.0
  der(a) = if x > 0.3021 then 1.0 else 0.0
  der(b) = if x < 0.302 then 0.0 else 1.0""")
    result = api.simulate(spec, 1.0, rtol=1e-8, atol=1e-10, points=3)
    listed = [(round(e["time"], 6), e["event"], e["direction"]) for e in result.events]
    assert listed == [(0.302, "x < 0.302", "rising"), (0.3021, "x > 0.3021", "rising")]
    assert result["a"][-1] == pytest.approx(1.0 - 0.3021, abs=1e-7)
    assert result["b"][-1] == pytest.approx(1.0 - 0.302, abs=1e-7)


@pytest.mark.parametrize("relation, slope", [("x > 0", 1), ("x < 0", -1)])
def test_a_relation_that_starts_on_its_zero_and_leaves_it(tmp_path, each_codegen, relation, slope):
    """x = 0 at the start makes `relation` false; it is true from the first instant on, so y = t.
    The native driver (c) counts the exact zero as the relation's false side, so IDAS's root
    finding sees the sign change at t = 0 either way. CasADi's IDAS (vm) compares signs at its
    check times (zero counts as not positive): `x > 0` goes from 0 to positive, a crossing it
    locates near 0; `x < 0` from 0 to negative, none, and the relation stays false until its next
    call settles it: y(2) = 1.9 (measured)."""
    spec = model_file(tmp_path, "Leaves", f"""
  variable x::Real
  variable y::Real
relations
  initial x = 0
  initial y = 0
  der(x) = {slope}
  der(y) = if {relation} then 1.0 else 0.0""")
    result = api.simulate(spec, 2.0, rtol=1e-8, atol=1e-10, points=5)
    if each_codegen == "c":
        assert result.stats["integrator"] == "native"
        assert result["y"][-1] == pytest.approx(2.0, abs=1e-9)
        ((event,),) = [result.events]
        assert event["event"] == relation and event["time"] < 1e-12
        assert event["direction"] == ("rising" if slope > 0 else "falling")
    elif slope > 0:
        assert result.stats["integrator"] == "casadi"
        assert result["y"][-1] == pytest.approx(2.0, abs=1e-9) and len(result.events) == 1
    else:
        assert result.stats["integrator"] == "casadi"
        assert result["y"][-1] == pytest.approx(1.9, abs=1e-9) and result.events == []


def test_a_relation_true_only_between_two_checks_is_found(tmp_path, each_codegen):
    """der(w) exceeds 0.5 for 1.7 ms around t = 0.5225 of a 1 s run whose steps reach 0.5 ms at
    most: IDAS's root finding (c: native) sees it rise and fall at the steps around it; CasADi's
    IDAS (vm) samples it at 200 checks per call, 5 ms apart (0.520 and 0.525 around it), and sees
    neither crossing: y stays 0."""
    spec = model_file(tmp_path, "Bump", """
  parameter center::Real = 0.5225
  parameter width::Real = 0.001
  variable u::Real
  variable w::Real
  variable y::Real
relations
  initial u = 0
  initial w = 0
  initial y = 0
  der(u) = 1
  der(w) = exp(-((u - center) / width)^2)
  der(y) = if der(w) > 0.5 then 1.0 else 0.0""")
    result = api.simulate_compiled(api.compile(spec), 1.0, rtol=1e-8, atol=1e-10, points=11, max_step=5e-4)
    half = 0.001 * math.sqrt(math.log(2))
    if each_codegen == "c":
        assert result.stats["integrator"] == "native"
        assert result["y"][-1] == pytest.approx(2 * half, abs=1e-10)
        assert [(e["direction"], round(e["time"], 9)) for e in result.events] == \
            [("rising", round(0.5225 - half, 9)), ("falling", round(0.5225 + half, 9))]
    else:
        assert result.stats["integrator"] == "casadi"
        assert result["y"][-1] == 0.0 and result.events == []
