"""Relations on unknowns are locked between events (Modelica's semantics): IDAS never sees a
condition flip between Newton iterations, a located crossing flips it, and a call whose locked
branch has no value past its crossing is integrated once more with the relations live."""
from __future__ import annotations

import math

import numpy as np
import pytest

from compiler import api
from compiler.runtime.event_horizon import event_reach
from compiler.runtime.relations import LIVE, lock_indices, relation_values, settle_relations


def model_file(tmp_path, name: str, body: str) -> str:
    path = tmp_path / f"{name}.dyad"
    path.write_text(f"component {name}\n{body}\nend\n", encoding="utf-8")
    return str(path)


SLEW = """
  parameter Ts::Real = 1e-6
  parameter sr::Real = 2.0
  parameter u::Real = 1.0
  variable y::Real
  variable rate::Real
relations
  initial y = 0
  rate = (u - y) / Ts
  der(y) = ifelse(rate > sr, sr, ifelse(rate < -sr, -sr, rate))"""


def test_a_slew_rate_limiter_follows_its_closed_form(tmp_path):
    # y ramps at sr until the fast first-order law asks for less, at t1 = (u - sr Ts) / sr, then
    # relaxes with time constant Ts: y = u - sr Ts exp(-(t - t1) / Ts)
    spec = model_file(tmp_path, "Slew", SLEW)
    result = api.simulate(spec, 1.0, rtol=1e-8, atol=1e-10, points=11)
    t1 = (1.0 - 2.0 * 1e-6) / 2.0
    exact = np.where(result.time <= t1, 2.0 * result.time,
                     1.0 - 2.0e-6 * np.exp(-np.clip(result.time - t1, 0, None) / 1e-6))
    np.testing.assert_allclose(result["y"], exact, atol=1e-9)
    (event,) = result.events
    assert event["time"] == pytest.approx(t1, abs=1e-9) and "rate > sr" in event["event"]


HELD = """
  parameter A::Real = 1e5
  parameter wp::Real = 30.0
  parameter vmax::Real = 1.0
  parameter f::Real = 1.0
  variable q::Real
  variable q_sum::Real
  variable q_help::Real
relations
  initial q = 0
  q_sum = A * (2 * sin(2 * 3.141592653589793 * f * time) - q)
  q_help = ifelse(q_sum > vmax and q >= vmax, vmax,
                  ifelse(q_sum < -vmax and q <= -vmax, -vmax, q_sum))
  der(q) = wp * (q_help - q)"""


def test_a_high_gain_follower_is_held_on_its_limit_without_chattering(tmp_path):
    # the op-amp's output stage in small: q follows u = 2 sin(2 pi t) through a loop of gain
    # k = wp (A + 1) = 3e6 / s until it reaches vmax, where the condition q >= vmax holds it; it is
    # released where A (u - q) < vmax. Unsaturated, q' = k (a u - q), a = A / (A + 1), whose periodic
    # solution is q_lin = 2 a k (k sin wt - w cos wt) / (k^2 + w^2) (a transient from q(0) = 0),
    # so q = clip(q_lin, -vmax, vmax). At the parent commit, relations live in the residual, this
    # run failed at t = 0 (IDA_ERR_FAIL); live with this commit's shorter calls it takes 34.8 k
    # steps, locked 6.9 k
    spec = model_file(tmp_path, "Held", HELD)
    result = api.simulate(spec, 3.0, rtol=1e-8, atol=1e-10, points=301)
    w, k, a = 2 * math.pi, 30.0 * (1e5 + 1), 1e5 / (1e5 + 1)
    q_lin = 2 * a * k * (k * np.sin(w * result.time) - w * np.cos(w * result.time)) / (k * k + w * w)
    q_lin += 2 * a * k * w / (k * k + w * w) * np.exp(-k * result.time)        # from q(0) = 0
    np.testing.assert_allclose(result["q"], np.clip(q_lin, -1.0, 1.0), atol=1e-8)
    assert result.stats["steps"] < 20_000
    # q reaches +1 and -1 where q_lin does, located to the run's own error
    amplitude, lag = 2 * a * k / math.hypot(k, w), math.atan2(w, k)
    up = (math.asin(1 / amplitude) + lag) / w
    down = (math.pi + math.asin(1 / amplitude) + lag) / w
    held = [e["time"] for e in result.events if e["event"] in ("q >= vmax", "q <= -vmax")]
    for reached in [n + s for n in range(3) for s in (up, down)]:
        assert min(abs(t - reached) for t in held) < 1e-8


def test_a_tank_whose_locked_branch_has_no_value_past_empty_is_integrated_live_there(tmp_path):
    # Torricelli: h = (1 - k t / 2)^2 reaches 0 at t = 2 with zero slope; past it the locked branch
    # takes sqrt of a negative level and IDAS fails, so that call is repeated with the relation
    # live, which crosses into the `else` branch
    spec = model_file(tmp_path, "Torricelli", """
  parameter k::Real = 1.0
  variable h::Real
relations
  initial h = 1.0
  der(h) = if h > 0 then -k * sqrt(h) else 0""")
    result = api.simulate(spec, 4.0, rtol=1e-8, atol=1e-10, points=9)
    exact = np.maximum(1.0 - result.time / 2.0, 0.0) ** 2
    np.testing.assert_allclose(result["h"], exact, atol=1e-8)
    (event,) = result.events
    assert event["time"] == pytest.approx(2.0, abs=1e-4)


def test_the_lock_replaces_the_relation_inside_the_integrated_equations(tmp_path):
    compiled = api.compile(model_file(tmp_path, "Slew", SLEW)).model
    locks = compiled.metadata["relation_locks"]
    assert sorted(lock["operator"] for lock in locks) == ["<", ">"]
    index = lock_indices(compiled)
    p = compiled.parameter_vector()
    assert np.all(p[index] == LIVE)                    # the default: the relation as written
    x, z, t = np.array([0.5]), np.zeros(len(compiled.algebraic_names)), 0.0
    live = float(compiled.dae(x, z, p, t)[0])
    assert live == pytest.approx(2.0)                  # rate = 5e5 > sr: limited
    assert list(relation_values(compiled, x, z, p, t)) == [1.0, 0.0]
    held = p.copy()
    held[index] = [0.0, 0.0]                           # locked "not above, not below": the rate itself
    assert float(compiled.dae(x, z, held, t)[0]) == pytest.approx(0.5 / 1e-6)
    settled, _ = settle_relations(compiled, held, x, z, t)
    assert list(settled[index]) == [1.0, 0.0]
    assert np.all(settle_relations(compiled, settled, x, z, t, live=True)[0][index] == LIVE)


def _cubic_root(c: float) -> float:
    """The real y with y + y^3 = c."""
    return float(next(r.real for r in np.roots([1.0, 0.0, 1.0, -c]) if abs(r.imag) < 1e-12))


def test_locks_settle_through_an_algebraic_unknown_that_depends_on_them(tmp_path):
    # event iteration: the relation reads y, y's equation reads the relation
    compiled = api.compile(model_file(tmp_path, "Loop", """
  variable x::Real
  variable y::Real
relations
  initial x = 0.2
  der(x) = -1
  y + y^3 = x + ifelse(y > 0.5, 1.0, 0.0)""")).model
    assert compiled.algebraic_names == ["y"]
    index = lock_indices(compiled)
    p = compiled.parameter_vector()
    p[index] = 0.0
    # (x, z) solve the equations with the locks given: they stay where the relations agree
    settled, z = settle_relations(compiled, p, np.array([0.2]), np.array([_cubic_root(0.2)]), 0.0)
    assert list(settled[index]) == [0.0] and float(z[0]) == pytest.approx(_cubic_root(0.2))
    # both branches are consistent at x = 0.2: the lock keeps the one it holds
    p[index] = 1.0
    settled, z = settle_relations(compiled, p, np.array([0.2]), np.array([_cubic_root(1.2)]), 0.0)
    assert list(settled[index]) == [1.0] and float(z[0]) == pytest.approx(_cubic_root(1.2))
    # at x = -0.7 the held branch gives y = 0.28 < 0.5: the lock flips, y is solved again
    settled, z = settle_relations(compiled, p, np.array([-0.7]), np.array([_cubic_root(0.3)]), 0.0)
    assert list(settled[index]) == [0.0] and float(z[0]) == pytest.approx(_cubic_root(-0.7))


class _WithEvents:
    class events:             # noqa: N801 - stands for a CasADi Function with one output row
        @staticmethod
        def numel_out():
            return 1


class _WithoutEvents:
    events = None


def test_a_call_reaches_twice_the_time_since_the_last_event():
    at = [{"time": 1.0, "event": "a"}]
    assert event_reach(_WithoutEvents, at, 1.5, 10.0, 0.0, 10.0) == 10.0
    assert event_reach(_WithEvents, [], 0.0, 10.0, 0.0, 10.0) == pytest.approx(0.5)
    assert event_reach(_WithEvents, [], 0.5, 10.0, 0.0, 10.0) == pytest.approx(1.5)
    assert event_reach(_WithEvents, at, 1.5, 10.0, 0.0, 10.0) == pytest.approx(2.5)
    assert event_reach(_WithEvents, at, 1.0, 10.0, 0.0, 10.0) == pytest.approx(1.001)
    assert event_reach(_WithEvents, at, 6.0, 10.0, 0.0, 10.0) == 10.0


def test_an_unknown_read_by_its_own_equations_condition_jumps_where_the_condition_flips(tmp_path):
    # y = x + ifelse(y > 0.5, 1, 0) was solved for y by reading the rest at y = 0, condition
    # included: y = x for ever. Kept implicit, y follows x until y = 0.5 (t = 0.3), where the
    # locked relation flips and y jumps to x + 1
    spec = model_file(tmp_path, "Implicit", """
  variable x::Real
  variable y::Real
relations
  initial x = 0.2
  der(x) = 1
  y = x + ifelse(y > 0.5, 1.0, 0.0)""")
    result = api.simulate(spec, 1.0, rtol=1e-8, atol=1e-10, points=11)
    (event,) = result.events
    assert event["time"] == pytest.approx(0.3, abs=1e-9)
    after = result.time > 0.3 + 1e-9
    np.testing.assert_allclose(result["y"], result["x"] + np.where(after, 1.0, 0.0), atol=1e-9)


def test_a_sliding_mode_stops_the_run_with_its_condition_named(tmp_path):
    # each branch drives v across 0 (v reaches it at t = 2): locked, every flip is an event a few
    # picoseconds after the last; the run says so instead of creeping on for ever
    from compiler.errors import DyadError
    spec = model_file(tmp_path, "Slide", """
  variable v::Real
relations
  initial v = 1.0
  der(v) = ifelse(v > 0, -1.0, 1.0) + 0.5""")
    with pytest.raises(DyadError) as caught:
        api.simulate(spec, 4.0, points=9, rtol=1e-6)
    assert caught.value.time_reached == pytest.approx(2.0, abs=1e-6)
    assert "the condition v > 0 switches back and forth (20 times within" in str(caught.value)
    assert "a sliding mode" in str(caught.value)
