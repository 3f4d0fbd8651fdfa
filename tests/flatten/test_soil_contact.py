"""The seed SoilContact (components/.../excavator/SoilContact.dyad) flattens unchanged, and a
body carrying it flattens balanced."""
from __future__ import annotations

from pathlib import Path

import sympy

from compiler.model.flatten import check_balance, flatten_model
from compiler.model.library_path import shipped_library_root
from tests.flatten.test_connect import PLANAR

SOIL = "MultibodyComponents.PlanarMechanics.examples.excavator.SoilContact"


def test_seed_source_is_unchanged_in_the_library():
    seed = Path("/work/shared/seeds/000_f4faa56a3475f571.txt")
    library_file = shipped_library_root() / "MultibodyComponents/PlanarMechanics/examples/excavator/SoilContact.dyad"
    if seed.is_file():
        text = seed.read_text(encoding="utf-8")
        source = text.split("Source\n\ndyad\n", 1)[1].split("\nFlattened Source", 1)[0]
        assert source.strip() == library_file.read_text(encoding="utf-8").strip()


def test_soil_contact_flattens():
    flat = flatten_model(SOIL)
    names = [v.name for v in flat.variables]
    assert names[:10] == ["y", "vx", "vy", "d", "F_cut", "F_x", "F_y", "m_load", "g_vec[1]",
                          "g_vec[2]"]
    assert flat.variable("m_load").kind == "state_candidate"
    assert flat.variable("m_load").start == 0
    assert [str(e.residual) for e in flat.initial_equations] == ["m_load"]
    assert "g_vec[2] + 9.80665" in {str(e.residual) for e in flat.equations}
    values = flat.parameter_values()
    assert values["gamma_s"] == 15700 and values["eps_c"] == 1e-3 and values["k_phi"] == 1.2e6
    # visual-only parts: the inherited Renderable parameters and the slab BoxShape
    assert "render" not in values and "slab_shape.width" not in values
    assert flat.visual["slab_shape"]["parameters"]["width"] == 7.0
    assert flat.visual["slab_shape"]["parameters"]["color"] == [0.47, 0.35, 0.2, 1.0]
    assert flat.visual[""]["parameters"]["render"] is True
    assert flat.metadata["instances"][""]["Dyad"]["icons"]


def test_body_with_soil_contact_flattens_balanced(sources):
    flat = sources.flatten(PLANAR + f"""
component Digger
  world = World()
  slider = Revolute(phi(initial = -1.0))
  arm = FixedTranslation(r = [2.0, 0])
  body = Body(m = 50, I = 2)
  soil = {SOIL}(c_v = 1e5)
relations
  connect(world.frame_b, slider.frame_a)
  connect(slider.frame_b, arm.frame_a)
  connect(arm.frame_b, body.frame_a, soil.frame_a)
end
""", "Digger")
    check_balance(flat)
    assert flat.parameter_values()["soil.c_v"] == 1e5
    flows = {str(e.residual) for e in flat.equations if e.kind == "flow"}
    assert "-arm.frame_b.fx - body.frame_a.fx - soil.frame_a.fx" not in flows
    assert any("soil.frame_a.fx" in f and "body.frame_a.fx" in f for f in flows)
    assert sympy.Symbol("der(soil.m_load)") in set().union(*(e.residual.free_symbols
                                                               for e in flat.equations))
    assert "soil.slab_shape" in flat.visual
