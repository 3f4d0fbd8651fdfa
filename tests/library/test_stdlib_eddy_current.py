"""The eddy-current brakes TranslationalComponents.Sources.EddyCurrentForce and
RotationalComponents.Sources.EddyCurrentTorque: Kloss' law at constant speed (cold and hot, below
and above the nominal speed), the heat flow equal to the mechanical power, and the kinetic energy
of a braked mass or flywheel found again in a heat capacitor; model
tests/models/Stdlib/EddyCurrentBrakes.dyad."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled

T_REF = 293.15


@pytest.fixture(scope="module")
def run():
    return Compiled().run("EddyCurrentBrakes", 2.0, points=201)


def kloss(nominal, speed, speed_nominal, alpha, temperature):
    x = speed / (speed_nominal * (1 + alpha * (temperature - T_REF)))
    return 2 * nominal * x / (1 + x * x)


@pytest.mark.parametrize("brake, v, f_nominal, v_nominal, alpha, temperature", [
    ("brake_slow", 4.0, 100, 10, 0.0, 293.15),
    ("brake_hot", -25.0, 100, 10, 0.004, 393.15),
])
def test_force_follows_kloss_law_at_constant_speed(run, brake, v, f_nominal, v_nominal, alpha,
                                                   temperature):
    expected = kloss(f_nominal, v, v_nominal, alpha, temperature)
    np.testing.assert_allclose(run[f"{brake}.f"], expected, rtol=1e-10)
    np.testing.assert_allclose(run[f"{brake}.flange.f"], expected, rtol=1e-10)
    np.testing.assert_allclose(run[f"{brake}.support.f"], -expected, rtol=1e-10)
    np.testing.assert_allclose(-run[f"{brake}.heat_port.Q_flow"], expected * v, rtol=1e-10)
    assert expected * v > 0         # braking in either direction: heat always leaves


def test_torque_follows_kloss_law_at_constant_speed(run):
    expected = -kloss(8, 30.0, 10, 0.004, 343.15)
    np.testing.assert_allclose(run["disc_fast.tau"], expected, rtol=1e-10)
    np.testing.assert_allclose(run["disc_fast.spline.tau"], -expected, rtol=1e-10)
    np.testing.assert_allclose(-run["disc_fast.heat_port.Q_flow"], -expected * 30.0, rtol=1e-10)


@pytest.mark.parametrize("kinetic, heat", [
    (lambda r: 0.5 * 2 * r["mass.v"] ** 2, lambda r: 40 * (r["fin.T"] - T_REF)),
    (lambda r: 0.5 * 0.5 * r["flywheel.w"] ** 2, lambda r: 25 * (r["rotor.T"] - T_REF)),
])
def test_braking_turns_kinetic_energy_into_heat(run, kinetic, heat):
    lost = kinetic(run)[0] - kinetic(run)
    assert lost[-1] > 0.5 * kinetic(run)[0]
    np.testing.assert_allclose(heat(run), lost, rtol=1e-6, atol=1e-6)


def test_heated_brake_slows_a_mass_along_kloss_law(run):
    force = kloss(50, run["mass.v"], 5, 0.004, run["fin.T"])
    np.testing.assert_allclose(-2 * run["mass.a"], force, rtol=1e-9, atol=1e-9)
