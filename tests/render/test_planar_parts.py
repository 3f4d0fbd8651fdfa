"""Which parts the side view finds in a flat model, and the geometry it derives from them."""
from __future__ import annotations

import numpy as np
import pytest

from compiler import api
from compiler.errors import DyadError
from compiler.render import animate, planar
from tests.render.conftest import MODELS


def test_excavator_parts_are_three_links_three_cylinders_and_the_soil_slab(excavator):
    scene = planar.discover(excavator.flat)
    assert [link.path for link in scene.links] == ["boom", "stick", "bucket"]
    assert [c.path for c in scene.cylinders] == ["boom_mount.mount", "stick_mount.mount", "bucket_mount.mount"]
    assert [box.path for box in scene.boxes] == ["soil.slab_shape"]
    assert [tool.path for tool in scene.tools] == ["soil"]
    assert [joint.path for joint in scene.joints] == ["boom_joint", "stick_joint", "bucket_joint"]
    assert [g.path for g in scene.grounds] == ["world"]


def test_parts_inside_a_link_are_not_drawn_twice_but_mount_brackets_are(excavator):
    scene = planar.discover(excavator.flat)
    bars = {bar.path for bar in scene.bars}
    assert not any(path.startswith(("boom.", "stick.", "bucket.")) for path in bars)
    assert bars == {"boom_base"} | {f"{axis}_mount.{side}_offset" for axis in ("boom", "stick", "bucket")
                                    for side in ("base", "rod")}
    assert scene.bodies == []                       # every Body sits inside a BodyShape
    assert scene.links[0].center_of_mass == "boom.body.frame_a"


def test_cylinder_parameters_and_tool_capacity_come_from_the_flat_parameters(excavator):
    scene = planar.discover(excavator.flat)
    boom = scene.cylinders[0]
    assert (boom.base, boom.rod) == ("boom_mount.mount.frame_a", "boom_mount.mount.frame_b")
    assert (boom.retracted_length, boom.stroke) == (0.988, 0.65)
    assert scene.tools[0].capacity == 150.0
    assert scene.tools[0].payload == "soil.m_load"


def test_soil_slab_is_a_rectangle_with_its_top_face_on_the_surface(excavator):
    slab = planar.discover(excavator.flat).boxes[0]
    xs, ys = zip(*slab.polygon)
    assert (min(xs), max(xs)) == pytest.approx((1.5 - 3.5, 1.5 + 3.5))
    assert (min(ys), max(ys)) == pytest.approx((-0.5, 0.0))
    assert len(slab.polygon) == 4
    assert slab.color == pytest.approx((0.47, 0.35, 0.2, 1.0))


def test_box_along_a_slanted_direction_projects_to_a_rotated_rectangle():
    box = planar.box_from_parameters("b", {"r": [1, 1, 0], "length_direction": [1, 1, 0],
                                           "width_direction": [0, 1, 0], "length": 2 ** 0.5,
                                           "width": 2 ** 0.5, "height": 5.0})
    corners = sorted((round(x, 9), round(y, 9)) for x, y in box.polygon)
    # length along the diagonal to (2, 2); width across it (orthogonalised to [-1, 1]/sqrt 2), centred
    assert corners == sorted([(0.5, 1.5), (1.5, 0.5), (1.5, 2.5), (2.5, 1.5)])


def test_convex_hull_drops_inner_and_repeated_points():
    hull = planar.convex_hull([(0, 0), (1, 0), (1, 1), (0, 1), (0.5, 0.5), (1, 1), (0.5, 0)])
    assert sorted(hull) == [(0, 0), (0, 1), (1, 0), (1, 1)]


def test_tool_is_carried_by_the_link_whose_end_it_follows(excavator, excavator_short_result):
    scene = planar.discover(excavator.flat)
    tracks = planar.FrameTracks(excavator_short_result, scene.frames())
    assert tracks.missing == []
    assert planar.carrier_of(scene.tools[0], scene, tracks).path == "bucket"


def test_cylinder_barrel_starts_at_the_base_and_the_rod_ends_at_the_rod_anchor():
    base, tip = np.array([0.0, 0.0]), np.array([3.0, 4.0])
    barrel_start, barrel_end, rod_start = animate.cylinder_geometry(base, tip, retracted_length=4.0)
    np.testing.assert_allclose(barrel_start, base)
    np.testing.assert_allclose(barrel_end, [1.8, 2.4])       # 0.75 * 4 along the unit vector (0.6, 0.8)
    np.testing.assert_allclose(rod_start, [0.9, 1.2])
    _, clamped_end, _ = animate.cylinder_geometry(base, tip, retracted_length=100.0)
    np.testing.assert_allclose(clamped_end, tip)             # the barrel never passes the rod anchor


def test_pendulum_has_one_link_one_joint_and_the_world(pendulum):
    summary = planar.discover(pendulum.flat).summary()
    assert (summary["links"], summary["joints"], summary["grounds"]) == (1, 1, 1)
    assert (summary["cylinders"], summary["boxes"], summary["tools"]) == (0, 0, 0)


def test_a_model_without_planar_parts_has_nothing_to_draw():
    flat = api.flatten("ComponentTests.ValveFlow", [str(MODELS)])
    result = type("NoSignals", (), {"time": np.array([0.0, 1.0]), "__contains__": lambda self, n: False})()
    with pytest.raises(DyadError) as caught:
        animate.prepare(flat, result)
    assert caught.value.message.startswith("nothing to draw: ")
    assert caught.value.span is not None and caught.value.span.file.endswith("ValveFlow.dyad")
