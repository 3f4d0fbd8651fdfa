"""Physics of the library components, checked against closed-form solutions.

Each test simulates a small model of tests/models/ComponentTests/ and compares named signals with
a solution derived by hand in the comments. The model defaults are repeated here as constants
(the models are the source of truth; a changed default must be changed in both places).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest


from compiler.api import simulate  # noqa: E402

MODELS = Path(__file__).resolve().parent.parent / "models"
G = 9.80665

# Tight solver tolerances so that the comparisons below test the equations, not the integrator.
TIGHT = dict(lib_dirs=(str(MODELS),), rtol=1e-9, atol=1e-9)


def run(model: str, stop: float, **kwargs):
    return simulate(f"ComponentTests.{model}", stop, **{**TIGHT, **kwargs})


# --------------------------------------------------------------------------------- mechanics

def test_free_body_flies_a_parabola_and_spins_uniformly():
    # No force on the frame: a = [0, -g], alpha = 0. From r0 = [0.5, 10], v0 = [1.5, 3],
    # phi0 = 0.2, w0 = -0.7:  x = 0.5 + 1.5 t,  y = 10 + 3 t - g t^2 / 2,  phi = 0.2 - 0.7 t.
    res = run("FallingBody", 1.0)
    t = res.time
    np.testing.assert_allclose(res["body.r[1]"], 0.5 + 1.5 * t, atol=1e-7)
    np.testing.assert_allclose(res["body.r[2]"], 10 + 3 * t - G * t**2 / 2, atol=1e-7)
    np.testing.assert_allclose(res["body.v[2]"], 3 - G * t, atol=1e-7)
    np.testing.assert_allclose(res["body.a[2]"], -G, atol=1e-6)
    np.testing.assert_allclose(res["body.phi"], 0.2 - 0.7 * t, atol=1e-7)
    np.testing.assert_allclose(res["body.w"], -0.7, atol=1e-7)


# Pendulum.dyad: link of length L with all its mass at the tip (r_cm = r = [L, 0]).
PEND_L, PEND_M, PEND_I, PEND_PHI0 = 0.8, 1.5, 0.02, -1.2


def pendulum_period(amplitude: float) -> float:
    # About the pivot, J = I + m L^2 and the gravity torque is r x F = L cos(phi) * (-m g), so
    # J phi'' = -m g L cos(phi). With theta = phi + pi/2 (angle from hanging straight down):
    # theta'' = -Omega^2 sin(theta), Omega^2 = m g L / J, whose exact period is
    # T = 4 K(k^2) / Omega with k = sin(amplitude / 2) (complete elliptic integral K).
    from scipy.special import ellipk
    omega = math.sqrt(PEND_M * G * PEND_L / (PEND_I + PEND_M * PEND_L**2))
    return 4 * ellipk(math.sin(amplitude / 2) ** 2) / omega


def test_pendulum_swings_with_the_exact_large_amplitude_period_and_conserves_energy():
    amplitude = PEND_PHI0 + math.pi / 2          # released at rest 0.37 rad from the bottom
    period = pendulum_period(amplitude)
    res = run("Pendulum", period, points=501)    # 501 points: index 250 is exactly half a period
    phi, w = res["joint.phi"], res["joint.w"]
    # Half a period later it is at the opposite turning point, after a full period back at start.
    assert phi[250] == pytest.approx(-math.pi / 2 - amplitude, abs=1e-6)
    assert w[250] == pytest.approx(0.0, abs=1e-5)
    assert phi[-1] == pytest.approx(PEND_PHI0, abs=1e-6)
    # Energy: kinetic 1/2 J w^2 plus potential m g y_cm with y_cm = L sin(phi).
    J = PEND_I + PEND_M * PEND_L**2
    energy = 0.5 * J * w**2 + PEND_M * G * PEND_L * np.sin(phi)
    np.testing.assert_allclose(energy, energy[0], atol=1e-6)
    # The centre of mass stays on the circle of radius L (joint and bars are rigid).
    radius = np.hypot(res["link.body.r[1]"], res["link.body.r[2]"])
    np.testing.assert_allclose(radius, PEND_L, atol=1e-7)


# Lever.dyad: left mass 5 kg at 0.5 m, right mass 2 kg at 1.25 m (equal moments 2.5 kg m).
LEVER_LEFT = dict(m=5.0, L=0.5, I=0.01)
LEVER_RIGHT = dict(m=2.0, L=1.25, I=0.03)


def test_balanced_lever_stays_at_rest_and_the_pivot_carries_the_weight():
    # Moments about the pivot: +m_l g L_l (left weight turns CCW) - m_r g L_r = 0.
    res = run("Lever", 1.0)
    np.testing.assert_allclose(res["pivot.phi"], 0.0, atol=1e-9)
    np.testing.assert_allclose(res["pivot.w"], 0.0, atol=1e-9)
    # The world pushes the lever up with the total weight: force on the joint through frame_a.
    weight = (LEVER_LEFT["m"] + LEVER_RIGHT["m"]) * G
    np.testing.assert_allclose(res["pivot.frame_a.fy"], weight, rtol=1e-9)
    np.testing.assert_allclose(res["pivot.frame_a.fx"], 0.0, atol=1e-9)
    np.testing.assert_allclose(res["world.frame_b.fy"], -weight, rtol=1e-9)
    # The massless right bar passes the right weight on: force on the bar at its far end is
    # minus the force on the body, which (at rest) holds the body against gravity: m_r g down.
    np.testing.assert_allclose(res["right_arm.frame_b.fy"], -LEVER_RIGHT["m"] * G, rtol=1e-9)


def test_unbalanced_lever_starts_with_the_predicted_angular_acceleration():
    # Right mass 3 kg: net moment (m_l L_l - m_r L_r) g = (2.5 - 3.75) g (clockwise), about a
    # pivot inertia J = sum(m L^2 + I). The lever is a physical pendulum:
    # J phi'' = (m_l L_l - m_r L_r) g cos(phi), so 1/2 J w^2 = (m_l L_l - m_r L_r) g sin(phi).
    m_right = 3.0
    moment = (LEVER_LEFT["m"] * LEVER_LEFT["L"] - m_right * LEVER_RIGHT["L"]) * G
    J = (LEVER_LEFT["m"] * LEVER_LEFT["L"] ** 2 + LEVER_LEFT["I"]
         + m_right * LEVER_RIGHT["L"] ** 2 + LEVER_RIGHT["I"])
    res = run("Lever", 0.5, params={"right_mass.m": m_right})
    assert res["left_mass.alpha"][0] == pytest.approx(moment / J, rel=1e-7)
    phi, w = res["pivot.phi"], res["pivot.w"]
    assert phi[-1] < -0.1                          # it really turned clockwise
    np.testing.assert_allclose(0.5 * J * w**2, moment * np.sin(phi), atol=1e-6)


# ---------------------------------------------------------------------------------- hydraulics

# CylinderHoldingLoad.dyad: load 250 kg standing on a vertical cylinder (area_a 3e-3 m^2,
# piston mass M = 10 kg, no gravity on the piston), mount s_offset 1.0, load starts at y = 1.2.
LOAD_M, PISTON_M, AREA_A, S_OFFSET, Y0 = 250.0, 10.0, 3e-3, 1.0, 1.2


def test_cylinder_holds_the_load_at_the_predicted_pressure():
    # Load and piston move together (s = y - s_offset): (m + M) a = area_a p_a - area_b p_b - m g
    # with the rod side at tank pressure 0. At rest exactly when p_a = m g / area_a.
    p_hold = LOAD_M * G / AREA_A                         # 817 220.8 Pa
    res = run("CylinderHoldingLoad", 1.0, params={"supply.p": p_hold})
    np.testing.assert_allclose(res["load.r[2]"], Y0, atol=1e-9)
    np.testing.assert_allclose(res["cylinder.s"], Y0 - S_OFFSET, atol=1e-9)
    np.testing.assert_allclose(res["cylinder.p_a"], p_hold, rtol=1e-12)
    np.testing.assert_allclose(res["cylinder.F_h"], LOAD_M * G, rtol=1e-9)
    # The mount passes the piston force to the load: force on the mount's flange = F_h - M a.
    np.testing.assert_allclose(res["mount.flange.f"], LOAD_M * G, rtol=1e-9)
    np.testing.assert_allclose(res["supply.port.q"], 0.0, atol=1e-12)


def test_cylinder_lifts_the_load_with_constant_acceleration_above_the_holding_pressure():
    # Default supply 1e6 Pa: a = (area_a p - m g) / (m + M) = (3000 - 2451.66) / 260 m/s^2,
    # y = y0 + a t^2 / 2; the supply delivers the swept volume: supply.port.q = -area_a v.
    p = 1e6
    accel = (AREA_A * p - LOAD_M * G) / (LOAD_M + PISTON_M)
    res = run("CylinderHoldingLoad", 0.5)
    t = res.time
    np.testing.assert_allclose(res["load.r[2]"], Y0 + accel * t**2 / 2, atol=1e-8)
    np.testing.assert_allclose(res["load.r[1]"], 0.0, atol=1e-9)
    np.testing.assert_allclose(res["cylinder.v"], accel * t, atol=1e-7)
    np.testing.assert_allclose(res["mount.L"], Y0 + accel * t**2 / 2, atol=1e-8)
    np.testing.assert_allclose(res["mount.flange.f"], AREA_A * p - PISTON_M * accel, rtol=1e-8)
    np.testing.assert_allclose(res["supply.port.q"], -AREA_A * accel * t, atol=1e-9)


def sreg(dp, d0):
    return dp / (dp**2 + d0**2) ** 0.25


def test_valve_flows_follow_the_regularised_orifice_law_over_a_command_sweep():
    # ValveFlow.dyad: P = 20 MPa, T = 0.5 MPa, A = 8 MPa, B = 12 MPa, Kv = 5e-7, Kv_b = 3e-7,
    # dp_small = 1e5, u_eps = 0.02 and u = -1 + t for t in [0, 2].
    # up = (u + sqrt(u^2 + eps^2)) / 2, un = (-u + sqrt(u^2 + eps^2)) / 2,
    # q_pa = Kv up sreg(P - A), q_at = Kv un sreg(A - T), q_pb = Kv_b un sreg(P - B),
    # q_bt = Kv_b up sreg(B - T); flows into the valve: port_p.q = q_pa + q_pb, etc.
    P, T, A, B, Kv, Kv_b, dp0, eps = 20e6, 0.5e6, 8e6, 12e6, 5e-7, 3e-7, 1e5, 0.02
    res = run("ValveFlow", 2.0, points=201)
    u = -1 + res.time
    up = (u + np.sqrt(u**2 + eps**2)) / 2
    un = (-u + np.sqrt(u**2 + eps**2)) / 2
    q_pa, q_at = Kv * up * sreg(P - A, dp0), Kv * un * sreg(A - T, dp0)
    q_pb, q_bt = Kv_b * un * sreg(P - B, dp0), Kv_b * up * sreg(B - T, dp0)
    np.testing.assert_allclose(res["valve.up"] - res["valve.un"], u, atol=1e-12)
    np.testing.assert_allclose(res["valve.q_pa"], q_pa, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(res["valve.q_bt"], q_bt, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(res["valve.port_p.q"], q_pa + q_pb, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(res["valve.port_a.q"], q_at - q_pa, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(res["valve.port_b.q"], q_bt - q_pb, rtol=1e-9, atol=1e-15)
    # Sources see the opposite flow; mass is conserved across the four ports.
    np.testing.assert_allclose(res["supply.port.q"], -(q_pa + q_pb), rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(res["tank.port.q"], q_at + q_bt, rtol=1e-9, atol=1e-15)
    # At u = 0 (t = 1) both openings are the underlap eps / 2.
    assert res["valve.up"][100] == pytest.approx(eps / 2, rel=1e-9)


# -------------------------------------------------------------------------------------- soil

# SoilContact defaults (sandy loam).
SOIL = dict(gamma_s=15700, rho_soil=1600, m_capacity=150, c_soil=4000, N_gamma=3.5, N_c=6.0,
            w=0.6, b=0.6, A_tip=0.018, n=0.8, k_c=3e4, k_phi=1.2e6, c_v=2e5, v_t=0.05, eps_c=1e-3)
BEKKER = SOIL["A_tip"] * (SOIL["k_c"] / SOIL["b"] + SOIL["k_phi"])     # 22 500 N / m^n


def smooth_depth(y):
    return (math.sqrt(y**2 + SOIL["eps_c"] ** 2) - y) / 2


def test_soil_resists_a_tool_dragged_at_constant_depth_and_fills_the_bucket():
    # SoilCutting.dyad: tip at y = -0.05 moving at vx = 0.2, vy = 0. Constant depth d, so
    # F_y = BEKKER d^n (no damping, vy = 0), F_cut = w (gamma d^2 N_gamma + c d N_c),
    # F_x = -F_cut tanh(vx / v_t). The payload obeys m' = R (1 - m / m_cap) with the constant
    # sweep rate R = rho w d vx tanh(vx / v_t), m(0) = 0: m = m_cap (1 - exp(-R t / m_cap)).
    vx, y = 0.2, -0.05
    d = smooth_depth(y)
    F_y = BEKKER * d ** SOIL["n"]
    F_cut = SOIL["w"] * (SOIL["gamma_s"] * d**2 * SOIL["N_gamma"] + SOIL["c_soil"] * d * SOIL["N_c"])
    F_x = -F_cut * math.tanh(vx / SOIL["v_t"])
    rate = SOIL["rho_soil"] * SOIL["w"] * d * vx * math.tanh(vx / SOIL["v_t"])
    res = run("SoilCutting", 5.0, points=101)
    t = res.time
    np.testing.assert_allclose(res["soil.d"], d, rtol=1e-12)
    np.testing.assert_allclose(res["soil.vx"], vx, rtol=1e-9)
    np.testing.assert_allclose(res["soil.vy"], 0.0, atol=1e-12)
    np.testing.assert_allclose(res["soil.F_y"], F_y, rtol=1e-9)
    np.testing.assert_allclose(res["soil.F_x"], F_x, rtol=1e-9)
    m_load = SOIL["m_capacity"] * (1 - np.exp(-rate * t / SOIL["m_capacity"]))
    np.testing.assert_allclose(res["soil.m_load"], m_load, rtol=1e-6, atol=1e-8)
    # The frame carries the reaction plus the payload weight (force on the soil component).
    np.testing.assert_allclose(res["soil.frame_a.fx"], -F_x, rtol=1e-9)
    np.testing.assert_allclose(res["soil.frame_a.fy"], -F_y + m_load * G, rtol=1e-6)


def test_body_sinks_into_the_soil_until_the_bekker_force_carries_its_weight():
    # SoilSinkage.dyad: 100 kg released at y = 0. At rest F_y = BEKKER d^n = m g, so
    # d_eq = (m g / BEKKER)^(1/n) (about 0.020 m). Inverting d = (sqrt(y^2 + eps^2) - y) / 2:
    # sqrt(y^2 + eps^2) = 2 d + y  =>  y_eq = (eps^2 - 4 d^2) / (4 d).
    # Linearised: stiffness n BEKKER d^(n-1) ~ 3.9e4 N/m, damping c_v d ~ 4e3 N s/m, so the
    # body is near critically damped (time constant ~ 0.05 s) and has settled after 3 s.
    m = 100.0
    d_eq = (m * G / BEKKER) ** (1 / SOIL["n"])
    y_eq = (SOIL["eps_c"] ** 2 - 4 * d_eq**2) / (4 * d_eq)
    res = run("SoilSinkage", 3.0)
    assert res["body.r[2]"][-1] == pytest.approx(y_eq, rel=1e-6)
    assert res["soil.d"][-1] == pytest.approx(d_eq, rel=1e-6)
    assert res["soil.F_y"][-1] == pytest.approx(m * G, rel=1e-6)
    assert abs(res["body.v[2]"][-1]) < 1e-6
    assert np.all(res["body.r[2]"] <= 1e-12)          # it only ever moves down into the soil
    # No horizontal motion: no cutting force, no payload.
    np.testing.assert_allclose(res["soil.F_x"], 0.0, atol=1e-9)
    np.testing.assert_allclose(res["soil.m_load"], 0.0, atol=1e-12)
