"""The excavator scene sources: every output signal of the scene spec (section 6) exists under its
exact name, the flattened model is balanced, and the initial pose reproduces the spec's derived
facts at t = 0 (section 7)."""
from __future__ import annotations

import pytest


from compiler.api import flatten, simulate  # noqa: E402

EXCAVATOR = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"
AXES = ("boom", "stick", "bucket")


def section6_signals() -> list[str]:
    names = [f"{a}_joint.{v}" for v in ("phi", "w") for a in AXES]
    names += ["boom.frame_b.x", "boom.frame_b.y", "stick.frame_b.x", "stick.frame_b.y",
              "bucket.frame_b.x", "bucket.frame_b.y", "bucket.frame_b.phi"]
    names += [f"soil.{v}" for v in ("vx", "vy", "d", "F_cut", "F_x", "F_y", "m_load")]
    for a in AXES:
        names += [f"{a}_cyl.cylinder.{v}" for v in ("s", "v", "p_a", "p_b", "F_h")]
        names += [f"{a}_cyl.force_sensor.f"]
        names += [f"{a}_cyl.controller.{v}" for v in ("v_set", "f_set", "z_v", "z_f", "u")]
        names += [f"{a}_mount.mount.L"]
    names += [f"reference.{k}_{a}" for a in AXES for k in ("s", "v")]
    names += ["supply.port.q", "tank.port.q"]
    return names


@pytest.fixture(scope="module")
def flat():
    return flatten(EXCAVATOR)


def test_every_output_signal_of_the_scene_spec_is_a_variable(flat):
    variables = {v.name for v in flat.variables}
    missing = [name for name in section6_signals() if name not in variables]
    assert not missing


def test_the_flat_excavator_is_balanced(flat):
    # Derivatives are unknowns of their own in the DAE F(x', x, y) = 0 but are not Variable
    # entries, so a square system has exactly one equation per variable.
    assert len(flat.equations) == len(flat.variables)


def test_the_initial_pose_matches_the_derived_facts_of_the_scene_spec():
    # Section 7 of the scene spec, computed there from the joint angles of section 4.
    res = simulate(EXCAVATOR, 0.01, points=2)
    expected = {
        "boom.frame_b.x": 2.112338387439514, "boom.frame_b.y": 2.4910520759656807,
        "stick.frame_b.x": 3.127228482638887, "stick.frame_b.y": 1.8507411400398546,
        "bucket.frame_b.x": 3.622821082528727, "bucket.frame_b.y": 1.6122291383828542,
        # Pistons at the first waypoint: L = s + s_offset.
        "boom_mount.mount.L": 0.490 + 0.988, "stick_mount.mount.L": 0.154 + 0.812,
        "bucket_mount.mount.L": 0.360 + 0.783,
        "boom_cyl.cylinder.F_h": 7744.106993081237, "stick_cyl.cylinder.F_h": 3661.5145857068364,
        "bucket_cyl.cylinder.F_h": 1790.6384314019163,
    }
    for name, value in expected.items():
        assert res[name][0] == pytest.approx(value, rel=1e-6), name
    assert res["soil.d"][0] == pytest.approx(1.5506e-7, rel=1e-3)
    assert res["boom_cyl.controller.u"][0] == pytest.approx(-0.00076265068342919, rel=1e-4)
    # It starts at rest: the references start with zero velocity and acceleration.
    assert abs(res["boom_joint.w"][-1]) < 1e-4
