"""RotationalComponents.Components.ElastoBacklash: an inertia rattling in an undamped backlash
follows free flight and half sine contacts and keeps its energy; with damping the contact never
pulls (model tests/models/Stdlib/BacklashRattle.dyad: J = 0.5, c = 200, b = 0.2, w(0) = 1).
TranslationalComponents.Components.ElastoGap: a mass bouncing off a wall through it
(tests/models/Stdlib/GapBounce.dyad: m = 1, c = 400, gap 0.1 m, v(0) = -1). The friction elements
that need a stuck/sliding mode are refused at their declaration."""
from __future__ import annotations

import math

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled

OMEGA = math.sqrt(200 / 0.5)
CONTACT = math.pi / OMEGA


@pytest.fixture(scope="module")
def run():
    return Compiled().run("BacklashRattle", 0.6, points=601)


def test_free_flight_then_a_half_sine_contact_then_back(run):
    t, phi, w = run.time, run["body.phi"], run["body.w"]
    free = t < 0.1 - 1e-3
    np.testing.assert_allclose(phi[free], t[free], atol=1e-7)
    contact = (t > 0.1 + 1e-3) & (t < 0.1 + CONTACT - 1e-3)
    np.testing.assert_allclose(phi[contact], 0.1 + np.sin(OMEGA * (t[contact] - 0.1)) / OMEGA, atol=1e-6)
    np.testing.assert_allclose(w[contact], np.cos(OMEGA * (t[contact] - 0.1)), atol=1e-5)
    back = (t > 0.1 + CONTACT + 1e-3) & (t < 0.3 + CONTACT - 1e-3)
    np.testing.assert_allclose(w[back], -1.0, atol=1e-5)
    np.testing.assert_allclose(run["play.tau"][back], 0.0, atol=0)


def test_undamped_rattle_keeps_its_energy(run):
    energy = 0.5 * 0.5 * run["body.w"] ** 2 + 0.5 * 200 * run["play.phi_contact"] ** 2
    np.testing.assert_allclose(energy, 0.25, rtol=1e-5)


def test_damped_contact_only_pushes_and_loses_energy(run):
    tau, contact = run["damped_play.tau"], run["damped_play.phi_contact"]
    assert np.all(tau * contact >= 0) and np.all(tau[contact == 0] == 0)
    energy = 0.5 * 0.5 * run["damped_body.w"] ** 2 + 0.5 * 200 * contact ** 2
    assert np.all(np.diff(energy) <= 1e-9) and energy[-1] < 0.2


def test_a_mass_bounces_off_an_elastic_gap_and_keeps_its_energy():
    run = Compiled().run("GapBounce", 0.4, points=401)
    t, s, v = run.time, run["body.s"], run["body.v"]
    omega = math.sqrt(400.0)
    free = t < 0.1 - 1e-3
    np.testing.assert_allclose(s[free], 0.1 - t[free], atol=1e-7)
    contact = (t > 0.1 + 1e-3) & (t < 0.1 + math.pi / omega - 1e-3)
    np.testing.assert_allclose(s[contact], -np.sin(omega * (t[contact] - 0.1)) / omega, atol=1e-6)
    after = t > 0.1 + math.pi / omega + 1e-3
    np.testing.assert_allclose(v[after], 1.0, atol=1e-5)
    np.testing.assert_allclose(run["gap.f"][after], 0.0, atol=0)
    energy = 0.5 * v ** 2 + 0.5 * 400 * np.minimum(s, 0) ** 2
    np.testing.assert_allclose(energy, 0.5, rtol=1e-5)


@pytest.mark.parametrize("name", ["RotationalComponents.Components.Clutch", "RotationalComponents.Brake",
                                  "TranslationalComponents.Components.SupportFriction"])
def test_a_stick_slip_friction_element_is_refused_at_its_declaration(tmp_path, name):
    from compiler.errors import DyadError
    from compiler.model.flatten import flatten_model
    path = tmp_path / "Rig.dyad"
    path.write_text(f"component Rig\n  body = RotationalComponents.Inertia(J = 1)\n"
                    f"  friction = {name}()\nend\n")
    with pytest.raises(DyadError) as err:
        flatten_model(str(path))
    assert (err.value.span.line, err.value.span.column) == (3, 3)
    package = name.split(".")[0]
    assert err.value.message == (f"`{name}` is a Coulomb friction element of Dyad's `{package}`: it "
                                 f"switches between stuck and sliding, a discrete mode that dyadc "
                                 f"cannot hold yet (no discrete states)")
