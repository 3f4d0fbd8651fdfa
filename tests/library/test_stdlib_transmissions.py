"""RotationalComponents' transmissions, motion sources and relative sensors against closed forms
and power balances (issue 27: IdealGearR2T, IdealRollingWheel, RackAndPinion, ...); the model is
tests/models/Stdlib/RotationalTransmissions.dyad, one independent set-up per component."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled


@pytest.fixture(scope="module")
def res():
    return Compiled().run("RotationalTransmissions", 2.0)


def test_rolling_wheel_moves_the_vehicle_with_the_wheels_reduced_inertia(res):
    # 2 N.m on J = 0.1 plus m r^2 = 4 * 0.5^2: phi'' = 2 / 1.1, s = r phi.
    t = res.time
    phi = (2 / 1.1) * t**2 / 2
    np.testing.assert_allclose(res["wheel_inertia.phi"], phi, atol=1e-8)
    np.testing.assert_allclose(res["vehicle.s"], 0.5 * phi, atol=1e-8)
    # The wheel is massless: the power it takes at the axle leaves at the flange.
    wheel_power = res["wheel.spline.tau"] * res["wheel_inertia.w"] + res["wheel.flange.f"] * res["vehicle.v"]
    np.testing.assert_allclose(wheel_power, 0, atol=1e-8)
    np.testing.assert_allclose(res["wheel.support_r.tau"], -res["wheel.spline.tau"], atol=1e-10)


def test_rack_and_pinion_is_the_rolling_wheel_with_the_pinion_radius(res):
    # 2 N.m on J = 0.05 plus 10 * 0.2^2: phi'' = 2 / 0.45, rack travel 0.2 phi.
    t = res.time
    np.testing.assert_allclose(res["rack.s"], 0.2 * (2 / 0.45) * t**2 / 2, atol=1e-8)


def test_r2t_gear_pushes_a_damper_at_speed_over_ratio_and_the_sensors_see_its_power(res):
    # 3 rad/s through 10 rad/m: v = 0.3 m/s, damper force 5 * 0.3, power 5 * 0.3^2 into the gear.
    np.testing.assert_allclose(res["load.f"], 1.5, atol=1e-9)
    np.testing.assert_allclose(res["power.power"], 0.45, atol=1e-9)
    np.testing.assert_allclose(res["multi.power"], 0.45, atol=1e-9)
    np.testing.assert_allclose(res["multi.w"], 3.0, atol=1e-9)
    np.testing.assert_allclose(res["multi.tau"], 0.15, atol=1e-9)
    np.testing.assert_allclose(res["r2t.support_t.f"], -res["r2t.flange.f"], atol=1e-10)


def test_planetary_gear_with_a_fixed_ring_follows_willis_and_conserves_energy(res):
    # Ring fixed: phi_sun = 3 phi_carrier; 2 N.m on the sun: w_c' = 3 * 2 / (9 * 0.1 + 0.9).
    t = res.time
    np.testing.assert_allclose(res["carrier_inertia.w"], (6 / 1.8) * t, atol=1e-8)
    np.testing.assert_allclose(res["sun_inertia.w"], 3 * res["carrier_inertia.w"], atol=1e-8)
    torques = res["planetary.sun.tau"] + res["planetary.carrier.tau"] + res["planetary.ring.tau"]
    np.testing.assert_allclose(torques, 0, atol=1e-9)


def test_motion_sources_impose_angle_speed_and_acceleration_and_relative_sensors_read_them(res):
    t = res.time
    np.testing.assert_allclose(res["angle_rel.phi_rel"], 0.3 * np.sin(2 * t), atol=1e-9)
    # The torque that moves J = 2 along 0.3 sin(2 t).
    np.testing.assert_allclose(res["angle_torque.tau"], 2 * -1.2 * np.sin(2 * t), atol=1e-6)
    np.testing.assert_allclose(res["speed_rel.w_rel"], 2 * t, atol=1e-9)
    np.testing.assert_allclose(res["speed_inertia.phi"], t**2, atol=1e-8)
    np.testing.assert_allclose(res["acceleration_rel.a_rel"], 1.5, atol=1e-9)
    np.testing.assert_allclose(res["acceleration_rel.w_rel"], 1.5 * t, atol=1e-8)
