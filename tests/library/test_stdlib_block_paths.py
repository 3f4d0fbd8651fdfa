"""BlockComponents under Dyad's documented sub-package paths and the flat paths of the published
repositories (one an alias of the other), and the blocks added with them, against closed forms;
model in tests/models/Stdlib/DyadBlockPaths.dyad."""
from __future__ import annotations

import math

import numpy as np
import pytest

from compiler.errors import DyadError
from compiler.model.library import Library
from tests.library.stdlib_support import Compiled


@pytest.fixture(scope="module")
def blocks():
    return Compiled().run("DyadBlockPaths", 3.0, points=601)


def at(result, name, t):
    return float(np.interp(t, result.time, result[name]))


def test_pi_on_a_constant_ramps_under_both_paths(blocks):
    t = blocks.time
    np.testing.assert_allclose(blocks["pi.y"], 3 * (2 + 2 * t / 0.5), rtol=1e-8, atol=1e-8)
    np.testing.assert_allclose(blocks["pi_flat.y"], blocks["pi.y"], rtol=0, atol=1e-12)


def test_pid_open_loop_response_to_a_constant_error(blocks):
    # e = 2: y = k (wp e + e t / Ti + Nd wd e exp(-Nd t / Td))
    t, e = blocks.time, 2.0
    expected = 2 * (0.5 * e + e * t / 0.25 + 5 * 0.8 * e * np.exp(-5 * t / 0.5))
    np.testing.assert_allclose(blocks["pid.y"], expected, rtol=1e-7, atol=1e-7)


def test_transfer_functions_step_responses(blocks):
    # input 2 from t = 0, starting at rest
    t = blocks.time
    np.testing.assert_allclose(blocks["lag.y"], 2 * (1 - np.exp(-2 * t)), atol=1e-8)
    # (2 s + 4) / ((s + 1)(s + 2)) = 2 / (s + 1): 2 * 2 (1 - exp(-t))
    np.testing.assert_allclose(blocks["second.y"], 4 * (1 - np.exp(-t)), atol=1e-8)
    # (s + 3) / (s + 1) = 1 + 2 / (s + 1): 2 (1 + 2 (1 - exp(-t)))
    np.testing.assert_allclose(blocks["lead.y"], 2 * (3 - 2 * np.exp(-t)), atol=1e-8)
    # its states: x[2] = u / (s^2 + 3 s + 2), x[1] = s x[2]
    np.testing.assert_allclose(blocks["second.x[2]"], 2 * (0.5 - np.exp(-t) + 0.5 * np.exp(-2 * t)), atol=1e-8)
    np.testing.assert_allclose(blocks["second.x[1]"], 2 * (np.exp(-t) - np.exp(-2 * t)), atol=1e-8)


def test_sine_and_cosine_of_variable_frequency(blocks):
    # f = 1 + 0.5 t for t < 2: phi = 0.2 + 2 pi (t + t^2 / 4); amplitude 2
    t = blocks.time
    early = t <= 2
    phi = 0.2 + 2 * math.pi * (t + t ** 2 / 4)
    np.testing.assert_allclose(blocks["chirp_sin.y"][early], (0.5 + 2 * np.sin(phi))[early], atol=1e-7)
    np.testing.assert_allclose(blocks["chirp_cos.y"][early], (2 * np.cos(phi))[early], atol=1e-7)
    # from t = 2 on the frequency stays 2 Hz
    late_phi = 0.2 + 2 * math.pi * (3 + 2 * (t - 2))
    np.testing.assert_allclose(blocks["chirp_cos.y"][~early], (2 * np.cos(late_phi))[~early], atol=1e-6)


def test_pid_with_an_external_derivative_and_its_limit(blocks):
    # e = 2, u_d = -3, u_ff = 2: v = 2 (0.5 * 2 + x_i - 3) + 0.5 * 2 = 2 x_i - 3 with
    # x_i' = e / Ti = 8, so v = 16 t - 3 until y reaches y_max = 20 at t0 = 23/16; then
    # Ti x_i' = e + (20 - v) / (k Ni) gives v' = -(8 / 1.8) (v - 23.6): the back-calculation
    # holds v at 20 + e k Ni = 23.6 instead of winding up
    t = blocks.time
    t0 = 23 / 16
    free = t < t0
    np.testing.assert_allclose(blocks["ext.y"][free], (16 * t - 3)[free], atol=1e-6)
    np.testing.assert_allclose(blocks["ext.y"][~free], 20.0, atol=1e-9)
    tracked = 23.6 - 3.6 * np.exp(-(8 / 1.8) * (t - t0))
    np.testing.assert_allclose(blocks["ext.v"][~free], tracked[~free], atol=1e-5)


def test_parts_removed_structurally_leave_no_state(blocks):
    # PD (with_I = false): y = k (wp e + Nd wd e exp(-Nd t / Td)), e = 2
    t = blocks.time
    np.testing.assert_allclose(blocks["pd.y"], 2 * (0.5 * 2 + 5 * 0.8 * 2 * np.exp(-5 * t / 0.5)),
                               rtol=1e-7, atol=1e-7)
    # limited P (with_I = with_D = false): clamp(k wp u_s, -3, 3) = clamp(4 * 2, -3, 3)
    np.testing.assert_allclose(blocks["p_only.y"], 3.0, atol=1e-12)
    np.testing.assert_allclose(blocks["p_only.x_i"], 0.0, atol=0)
    np.testing.assert_allclose(blocks["p_only.x_d"], 0.0, atol=0)


def test_limpid_differentiates_the_whole_error_by_default():
    # wd = 1: the published flat LimPID differentiates u_s - u_m (it declares wd = 0 but never
    # uses it), so both spellings of ours default to wd = 1 and are one definition
    from compiler.model.flatten import flatten_model
    for spelling in ("BlockComponents.LimPID", "BlockComponents.Continuous.LimPID"):
        system = flatten_model(spelling)
        assert next(p.value for p in system.parameters if p.name == "wd") == 1.0


def test_state_space_oscillator_about_its_operating_point(blocks):
    # x1'' + 0.4 x1' + 4 x1 = 4 (u - u0) = 4, x1(0) = 0.5, x1'(0) = 0: x1 = 1 - 0.5 e^(-0.2 t)
    # (cos(wd t) + 0.2 / wd sin(wd t)), wd = sqrt(4 - 0.04); y1 = x1 + 0.5, y2 = 2 x2 + 0.1 (u - u0)
    t = blocks.time
    wd = math.sqrt(4 - 0.04)
    x1 = 1 - 0.5 * np.exp(-0.2 * t) * (np.cos(wd * t) + 0.2 / wd * np.sin(wd * t))
    x2 = 0.5 * np.exp(-0.2 * t) * (0.04 / wd + wd) * np.sin(wd * t)
    np.testing.assert_allclose(blocks["oscillator.x[1]"], x1, atol=1e-7)
    np.testing.assert_allclose(blocks["oscillator.y[1]"], x1 + 0.5, atol=1e-7)
    np.testing.assert_allclose(blocks["oscillator.y[2]"], 2 * x2 + 0.1, atol=1e-6)


def test_clock_exp_sine_and_gain(blocks):
    assert at(blocks, "clock.y", 0.5) == pytest.approx(0.5, abs=1e-12)
    assert at(blocks, "clock.y", 2.5) == pytest.approx(2.0, abs=1e-9)
    t = blocks.time
    damped = 0.1 + 2 * np.exp(-0.5 * t) * np.sin(2 * math.pi * 1.5 * t + 0.3)
    np.testing.assert_allclose(blocks["exp_sine.y"], damped, atol=1e-9)
    np.testing.assert_allclose(blocks["gain.y"], -3.0, atol=1e-12)
    np.testing.assert_allclose(blocks["inverse.y"], 0.5, atol=1e-12)        # 4 y = 2
    np.testing.assert_allclose(blocks["sum3.y"], 2 - 2 * blocks["step.y"] + 0.5 * blocks["clock.y"],
                               atol=1e-12)
    assert at(blocks, "sum3.y", 2.5) == pytest.approx(2 - 2 + 0.5 * 2.0, abs=1e-9)


@pytest.mark.parametrize("t, square, triangle", [
    (0.1, -0.5, -0.5),                    # before start_time: the offset
    (0.3, 1.0, -0.5 - 1.5 + 1.5 * 4 * 0.125),   # first half of the period: high, rising
    (0.7, -2.0, -0.5 + 1.5 - 1.5 * 4 * 0.125),  # second half: low, falling
    (1.1, 1.0, -0.5 - 1.5 + 1.5 * 4 * 0.125),   # one period later
])
def test_square_and_triangle_waves(blocks, t, square, triangle):
    assert at(blocks, "square.y", t) == pytest.approx(square, abs=1e-9)
    assert at(blocks, "triangle.y", t) == pytest.approx(triangle, abs=1e-6)


def test_variable_limiter_follows_its_limit_signals(blocks):
    expected = np.minimum(np.maximum(blocks["clock.y"], 0.0), blocks["lag.y"])
    np.testing.assert_allclose(blocks["band.y"], expected, atol=1e-12)
    assert at(blocks, "band.y", 0.1) == pytest.approx(2 * (1 - math.exp(-0.2)), abs=1e-7)   # upper
    assert at(blocks, "band.y", 1.5) == pytest.approx(1.0, abs=1e-7)                      # passes u


def test_slew_rate_limiter_rises_at_its_limit(blocks):
    assert at(blocks, "slew.y", 0.4) == pytest.approx(0.0, abs=1e-9)
    assert at(blocks, "slew.y", 0.75) == pytest.approx(0.5, abs=1e-4)
    assert at(blocks, "slew.y", 2.5) == pytest.approx(1.0, abs=1e-6)


def test_flat_path_is_an_alias_of_the_documented_one():
    library = Library()
    documented = library.lookup("BlockComponents.Continuous.PID", "", None)
    flat = library.lookup("BlockComponents.PID", "", None)
    assert flat is documented
    assert flat.qualified_name == "BlockComponents.Continuous.PID"
    assert library.find_aliased("BlockComponents.Interfaces.SISO") is None   # not a flat path


def write(path, text):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


def test_a_definition_at_the_top_level_wins_over_the_alias(tmp_path):
    write(tmp_path / "P" / "X.dyad", "component X\n  parameter a::Real = 1\nend\n")
    write(tmp_path / "P" / "S" / "X.dyad", "component X\n  parameter b::Real = 1\nend\n")
    found = Library([tmp_path]).lookup("P.X", "", None)
    assert found.qualified_name == "P.X"


def test_a_name_in_two_subpackages_is_no_alias_and_the_hint_lists_both(tmp_path):
    write(tmp_path / "P" / "A" / "X.dyad", "component X\nend\n")
    write(tmp_path / "P" / "B" / "X.dyad", "component X\nend\n")
    library = Library([tmp_path])
    assert library.lookup("P.X", "", None) is None
    with pytest.raises(DyadError) as err:
        library.resolve("P.X", "", None, None, what="component type")
    assert err.value.hint == ("`P.X` is defined in more than one subpackage of `P`; name one: "
                              "`P.A.X`, `P.B.X`")


def test_a_sampled_component_is_refused_at_its_declaration(tmp_path):
    path = tmp_path / "Loop.dyad"
    path.write_text("component Loop\n  plant = BlockComponents.Continuous.FirstOrder(T = 1)\n"
                    "  hold = DiscreteComponents.ZeroOrderHold()\nrelations\n"
                    "  connect(hold.y, plant.u)\nend\n")
    from compiler.model.flatten import flatten_model
    with pytest.raises(DyadError) as err:
        flatten_model(str(path))
    assert (err.value.span.line, err.value.span.column) == (3, 3)
    assert err.value.message == ("`DiscreteComponents.ZeroOrderHold` is a sampled (discrete-time) "
                                 "component of Dyad's `DiscreteComponents`; dyadc does not simulate "
                                 "clocked (sampled) components yet")


def test_a_size_taken_from_the_value_needs_a_value(tmp_path):
    path = tmp_path / "Open.dyad"
    path.write_text("component Open\n  parameter a::Real[:]\n  variable x::Real\n"
                    "relations\n  der(x) = -sum(a) * x\nend\n")
    from compiler.model.flatten import flatten_model
    with pytest.raises(DyadError) as err:
        flatten_model(str(path))
    assert err.value.message == "parameter `a` takes its size from its value (`:`) but has no value"
    assert (err.value.span.line, err.value.span.column) == (2, 21)   # the `:`
