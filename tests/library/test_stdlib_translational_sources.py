"""TranslationalComponents' motion sources, relative sensors, power sensors, Rod and the
IdealGearR2T it re-exports, against closed forms; model tests/models/Stdlib/TranslationalSources."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled


@pytest.fixture(scope="module")
def res():
    return Compiled().run("TranslationalSources", 2.0)


def test_position_source_moves_the_mass_along_its_reference(res):
    t = res.time
    np.testing.assert_allclose(res["position_rel.s_rel"], 0.2 * np.sin(3 * t), atol=1e-9)
    # The force that moves m = 2 along 0.2 sin(3 t).
    np.testing.assert_allclose(res["position_force.f"], 2 * -1.8 * np.sin(3 * t), atol=1e-6)


def test_speed_source_pulls_rod_and_damper_and_the_sensors_see_the_power(res):
    t = res.time
    np.testing.assert_allclose(res["speed_rel.v_rel"], 0.5, atol=1e-9)
    np.testing.assert_allclose(res["rod.flange_b.s"], 0.5 * t + 0.3, atol=1e-9)
    np.testing.assert_allclose(res["damper.f"], 2.0, atol=1e-9)
    np.testing.assert_allclose(res["multi.f"], 2.0, atol=1e-9)
    np.testing.assert_allclose(res["multi.v"], 0.5, atol=1e-9)
    np.testing.assert_allclose(res["multi.power"], 1.0, atol=1e-9)
    np.testing.assert_allclose(res["power.power"], 1.0, atol=1e-9)


def test_acceleration_source_accelerates_uniformly(res):
    t = res.time
    np.testing.assert_allclose(res["accelerate_rel.a_rel"], 2.0, atol=1e-9)
    np.testing.assert_allclose(res["accelerated_mass.v"], 2 * t, atol=1e-8)
    np.testing.assert_allclose(res["accelerated_mass.s"], t**2, atol=1e-8)


def test_r2t_gear_moves_the_mass_with_the_reduced_inertia(res):
    # 1 N.m on J = 0.5 plus m / ratio^2 = 3 / 16: phi'' = 1 / 0.6875, s = phi / 4.
    t = res.time
    phi = t**2 / (2 * 0.6875)
    np.testing.assert_allclose(res["inertia.phi"], phi, atol=1e-8)
    np.testing.assert_allclose(res["gear_mass.s"], phi / 4, atol=1e-8)


def test_user_components_on_dyads_force_and_two_flange_partials():
    """A push on PartialForce and a 2:1 lever on PartialElementaryTwoFlangesAndSupport2, written
    the way a user extends them (tests/models/Stdlib/TranslationalPartials.dyad)."""
    res = Compiled().run("TranslationalPartials", 2.0)
    t = res.time
    np.testing.assert_allclose(res["mass1.s"], t**2, atol=1e-8)            # 3 N on 1.5 kg
    np.testing.assert_allclose(res["push.s"], res["mass1.s"], atol=1e-10)
    np.testing.assert_allclose(res["mass2.s"], 0.75 * t**2, atol=1e-8)     # 2 * 3 N on 4 kg
    # The ground takes the reaction of everything the masses gain: 3 N + 6 N.
    np.testing.assert_allclose(res["fixed.flange.f"], -9.0, atol=1e-9)
