"""Dyad's HydraulicComponents in dyadc's words (components/HydraulicComponents, media in its
src/*.jl), used from a model outside the package under both spellings, against closed forms and
mass balances; model tests/models/Stdlib/HydraulicMedia.dyad (medium: bulk modulus 1e9 Pa, no gas
phase, reference density 997 kg/m3 at 100325 Pa, viscosity 0.0010016 Pa.s)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled

RHO0, P0, BETA, MU = 997.0, 100325.0, 1e9, 0.0010016


def density(p):
    return RHO0 * (1 + (p - P0) / BETA)


def friction(m_flow, area, d_h, shape_factor=64.0):
    re = np.maximum(np.abs(m_flow) * d_h / (area * MU), 1.0)
    laminar = shape_factor / re
    turbulent = (shape_factor / 64) / (0.79 * np.log(re) - 1.64) ** 2
    w = np.clip((re - 2000) / 1000, 0, 1)
    return laminar + (turbulent - laminar) * w ** 2 * (3 - 2 * w)


@pytest.fixture(scope="module")
def run():
    return Compiled().run("HydraulicMedia", 2.0, points=801)


def test_a_volume_follows_its_boundary_and_takes_the_compressed_mass(run):
    t = run.time
    p = 1e5 + 1e6 * np.minimum(t, 1.0)
    np.testing.assert_allclose(run["tank.p"], p, rtol=1e-9)
    np.testing.assert_allclose(run["tank.m"], 2 * density(p), rtol=1e-12)
    # d(m)/dt = vol rho0 / beta dp/dt while the ramp rises, supplied by the boundary
    rising = (t > 0.01) & (t < 0.99)
    np.testing.assert_allclose(run["charger.port.m_flow"][rising], -2 * RHO0 / BETA * 1e6, rtol=1e-6)
    assert abs(run["charger.port.m_flow"][-1]) < 1e-9


def test_a_tube_loses_its_pressure_by_darcy_friction(run):
    area, length = 1e-4, 2.0
    d_h = 4 * area / (2 * math.sqrt(math.pi * area))
    m_flow = run["pipe.m_flow"]
    rho = density(3e5)
    np.testing.assert_allclose(run["pipe.rho"], rho, rtol=1e-12)
    np.testing.assert_allclose(run["pipe.ff"], friction(m_flow, area, d_h), rtol=1e-9)
    v = m_flow / (rho * area)
    expected = 0.5 * rho * v * np.sqrt(v ** 2 + 1e-6) * run["pipe.ff"] * length / d_h
    np.testing.assert_allclose(run["pipe.sheer"], expected, rtol=1e-9, atol=1e-6)
    # at rest the whole 2 bar drop is friction; mass passes through unchanged
    assert run["pipe.sheer"][-1] == pytest.approx(2e5, rel=1e-7)
    assert m_flow[-1] * d_h / (area * MU) > 3000          # turbulent at the end
    np.testing.assert_allclose(run["pipe.port_a.m_flow"], -run["pipe.port_b.m_flow"], atol=1e-12)


def test_a_divider_passes_a_quarter_and_mass_is_conserved(run):
    t, fed = run.time, run["feed.m_flow"]
    np.testing.assert_allclose(run["divider.m_flow_b"], fed / 4, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(run["spill.port.m_flow"], 3 * fed / 4, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(run["divider.port_a.p"], run["vessel.p"], rtol=1e-12)
    stored = run["vessel.m"] - run["vessel.m"][0]
    inflow = np.concatenate([[0.0], np.cumsum(np.diff(t) * (fed[1:] + fed[:-1]) / 8)])
    np.testing.assert_allclose(stored, inflow, rtol=0, atol=1e-4 * stored[-1])
    assert run["vessel.p"][-1] > 2.5e5                    # filling towards 3 bar


def test_a_piston_accelerates_under_its_pressures_and_rests_on_the_end_stop(run):
    t = run.time
    force = 3e5 * 1e-3 - 1e5 * 5e-4                        # 250 N on 100 kg
    free = t < math.sqrt(1.0 / (0.5 * force / 100)) - 1e-3
    np.testing.assert_allclose(run["cylinder.s"][free], (0.5 + 0.5 * force / 100 * t ** 2)[free], rtol=1e-7)
    np.testing.assert_allclose(run["cylinder.v"][free], (force / 100 * t)[free], rtol=1e-7, atol=1e-10)
    np.testing.assert_allclose(run["cylinder.F_dp"], force, rtol=1e-12)
    # each chamber's fluid grows or shrinks with the swept volume at constant pressure
    np.testing.assert_allclose(run["cylinder.port_a.m_flow"], density(3e5) * 1e-3 * run["cylinder.v"],
                               rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(run["cylinder.port_b.m_flow"], -density(1e5) * 5e-4 * run["cylinder.v"],
                               rtol=1e-7, atol=1e-9)
    assert run["cylinder.s"][-1] == pytest.approx(1.5 + force / 1e8, abs=1e-9)
    assert run["cylinder.contact_force"][-1] == pytest.approx(-force, rel=1e-6)
