"""The excavator's soil contact made sharp, then stiffer: runtime overrides of one compilation.

"Sharp": the seed's smoothing lengths shrunk, eps_c 1 mm -> 1 um (contact onset) and v_t 5 cm/s ->
0.1 mm/s (friction sign). "n times stiffer": the soil's static force laws scaled by n at every
depth, i.e. k_c, k_phi (Bekker pressure-sinkage) and c_soil, gamma_s (Reece cutting resistance)
times n; c_v (damping) and rho_soil (payload density) unchanged (excavator_signals.SOIL_FORCE_LAW).

The physics that sets the bands: the bucket is position-controlled by three servo cylinders
tracking the same references, so as long as no cylinder reaches its force limit the bucket
follows the same path, the depth d and the swept payload stay nearly the same and the soil forces
scale with the force law. The limit that matters is the stick cylinder pulling the bucket through
the soil: its rod side at supply pressure gives at most P_SUPPLY * AREA_B = 50 kN. The default
scene peaks at 38 kN there, so a factor of about 1.3 exhausts the margin: 1.25 is followed,
ten times is not: the machine stalls, and then the run leaves the model's domain (last tests).
"""
from __future__ import annotations

import numpy as np
import pytest

from compiler import runtime
from tests.hard.excavator_signals import (AREA_A, AREA_B, CYLINDER_FORCES, P_SUPPLY, SHARP_CONTACT, SOIL_FORCES,
                                          peak, stiffer_soil)

V_DEAD = 2.5e-4
STICK_PULL_LIMIT = P_SUPPLY * AREA_B      # rod side at supply pressure, cap side at tank


@pytest.fixture(scope="module")
def sharp(excavator):
    return runtime.simulate(excavator.model, 12.0, points=1201, params=SHARP_CONTACT)


def test_sharp_contact_completes_close_to_the_smooth_one(excavator_default, sharp):
    default = excavator_default
    assert sharp.time[-1] == 12.0
    # Peak forces: the onset smoothing shifts the depth by at most eps_c / 2 = 0.5 mm against a
    # peak depth of 0.23 m (0.2 %), forces go with d^0.8 .. d^2 (Bekker, Reece): <= 0.5 %, and the
    # servos keep the path. Band 1 %. Measured: +0.25 % (F_x) .. +0.50 % (boom cylinder).
    for name in SOIL_FORCES + CYLINDER_FORCES + ("soil.d",):
        assert peak(sharp, name) == pytest.approx(peak(default, name), rel=0.01), name
    # Payload: the fill rate uses vx tanh(vx / v_t), which underestimates |vx| where the drag is
    # slow (|vx| ~ v_t = 5 cm/s) by up to (1 - tanh(1)) = 24 %; the sharp law does not. So the
    # sharp payload is larger, by the share of the sweep done at slow speed: band (0, 3 %].
    # Measured: 110.69 -> 112.05 kg (+1.2 %).
    m_default, m_sharp = default["soil.m_load"][-1], sharp["soil.m_load"][-1]
    assert 0.0 < (m_sharp - m_default) / m_default <= 0.03
    # The dig path: where the drag slows down (6 - 6.7 s) the sharp friction law sticks (vx = 0
    # while the servo force is below F_cut) where the regularized one creeps at |vx| ~ 0.025 -
    # 0.045 m/s, i.e. ~2 cm over those 0.7 s; the servos then catch up. So the tip stays within
    # 3 cm of the default path (measured 24 mm in x, 6 mm in y, at 6.7 s) and ends within 1 mm
    # (measured 0.02 mm).
    for name in ("bucket.frame_b.x", "bucket.frame_b.y"):
        np.testing.assert_allclose(sharp[name], default[name], atol=0.03, err_msg=name)
        assert sharp[name][-1] == pytest.approx(default[name][-1], abs=1e-3), name
    stuck = (sharp.time >= 6.25) & (sharp.time <= 6.5)
    assert np.all(np.abs(sharp["soil.vx"][stuck]) < 1e-3)
    assert np.all(np.abs(default["soil.vx"][stuck]) > 0.02)


def test_sharp_contact_in_a_25_percent_stiffer_soil_keeps_the_path_and_scales_the_forces(excavator, sharp):
    stiffer = runtime.simulate(excavator.model, 12.0, points=1201, params={**SHARP_CONTACT, **stiffer_soil(1.25)})
    assert stiffer.time[-1] == 12.0
    # No servo saturates (valve commands well inside +-1), the stick stays below its pulling limit.
    for axis in ("boom", "stick", "bucket"):
        assert peak(stiffer, f"{axis}_cyl.controller.u") < 0.9, axis
    assert peak(stiffer, "stick_cyl.force_sensor.f") < STICK_PULL_LIMIT
    # Same path, so the same depth and payload (1 %; measured -0.4 % and -0.04 %).
    assert peak(stiffer, "soil.d") == pytest.approx(peak(sharp, "soil.d"), rel=0.01)
    assert stiffer["soil.m_load"][-1] == pytest.approx(sharp["soil.m_load"][-1], rel=0.01)
    # The cutting resistance is the scaled law at (almost) the same depth: 1.25 within 3 %
    # (measured 1.244). The vertical reaction also carries the unscaled damping c_v d vy, so its
    # peak grows by less than 1.25 (measured 1.199).
    assert peak(stiffer, "soil.F_x") / peak(sharp, "soil.F_x") == pytest.approx(1.25, rel=0.03)
    assert 1.15 < peak(stiffer, "soil.F_y") / peak(sharp, "soil.F_y") <= 1.25
    # Cylinder forces: the soil share grows by 1.25, gravity and inertia shares do not, so each
    # peak grows by a factor between 1 and 1.25 (measured 1.21 .. 1.24).
    for name in CYLINDER_FORCES:
        assert 1.0 < peak(stiffer, name) / peak(sharp, name) <= 1.25, name


@pytest.fixture(scope="module")
def ten_times_stiffer_until_stop(excavator):
    """Up to just before the run breaks down (see the next test)."""
    return runtime.simulate(excavator.model, 7.4, points=741, params={**SHARP_CONTACT, **stiffer_soil(10)})


def test_ten_times_stiffer_soil_stalls_the_stick_at_its_pulling_limit(excavator_default, ten_times_stiffer_until_stop):
    run = ten_times_stiffer_until_stop
    t = run.time
    # The stick cylinder pulls as hard as the supply allows (rod side at 25 MPa, cap at tank):
    # its force reaches -P_SUPPLY * AREA_B = -50 kN (measured -50.05 kN, the extra is M a).
    assert run["stick_cyl.force_sensor.f"].min() == pytest.approx(-STICK_PULL_LIMIT, rel=0.005)
    # ... with its valve (nearly) fully open while the dig phase lasts (measured u <= -0.93).
    dig = (t >= 3.5) & (t <= 6.5)
    assert np.all(run["stick_cyl.controller.u"][dig] <= -0.9)
    # The bucket stays shallow and sweeps far less soil than in the default scene.
    assert peak(run, "soil.d") < 0.25 * peak(excavator_default, "soil.d")
    index = np.searchsorted(excavator_default.time, 7.4)
    assert run["soil.m_load"][-1] < 0.5 * excavator_default["soil.m_load"][index]


def test_ten_times_stiffer_soil_drives_the_stick_piston_past_its_stroke(ten_times_stiffer_until_stop):
    # No anti-windup and no end stops (scene spec 2.8, 2.12): when the stalled bucket finally breaks
    # free, the wound-up loops drive the stick piston past its retracted end s = 0, emptying the
    # cap chamber V_a = V_dead + AREA_A s, which vanishes at s = -V_dead / AREA_A = -83 mm.
    run = ten_times_stiffer_until_stop
    assert run["stick_cyl.cylinder.s"][-1] < -0.05                # measured -0.057 m at 7.4 s
    assert run["stick_cyl.cylinder.V_a"][-1] < 0.5 * V_DEAD
    assert run["stick_cyl.cylinder.V_a"][-1] == pytest.approx(V_DEAD + AREA_A * run["stick_cyl.cylinder.s"][-1])


def test_ten_times_stiffer_soil_stops_where_the_stick_cap_chamber_empties(excavator):
    # Volume has `min = 0` in the standard types and IDAS watches every declared bound while it
    # integrates; bounds="error" makes leaving one a stop (it is otherwise a warning). Over the
    # whole 12 s scene what happens is the stop: the stick piston, driven past its retracted end
    # (previous test), empties the cap chamber V_a = V_dead + AREA_A s at s = -83 mm. Measured:
    # stops at t = 7.4723 s, V_a = -1e-6 m^3, both at stop 8 s and 12 s. The run must not carry on
    # through an empty chamber, and must say which bound it left, where and when.
    stop = 12.0
    with pytest.raises(runtime.SimulationFailed) as stopped:
        runtime.simulate(excavator.model, stop, points=int(stop * 100) + 1,
                         params={**SHARP_CONTACT, **stiffer_soil(10)}, bounds="error")
    failure = stopped.value
    assert failure.variable == "stick_cyl.cylinder.V_a"
    assert 7.4 < failure.time_reached < 7.55            # after the 7.4 s state of the tests above
    message = str(failure)
    assert "left the model's domain at t = 7.4" in message
    assert "stick_cyl.cylinder.V_a" in message and "outside its declared min = 0" in message
