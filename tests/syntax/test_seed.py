"""The SoilContact seed: stored byte for byte, parses into the expected structure.

The seed text lives beside the repository, in the project's shared folder (../shared/seeds/). It
must be there in CI (the environment variable CI set) and wherever the shared folder exists; only
a checkout alone (a copy of the repository without the project around it) skips the byte check.
"""
import os
from pathlib import Path

import pytest

from compiler.syntax import ast
from compiler.syntax.parser import parse_file

ROOT = Path(__file__).resolve().parents[2]
SHARED = ROOT.parent / "shared"
SEED = SHARED / "seeds" / "000_f4faa56a3475f571.txt"
SOIL = ROOT / "components/MultibodyComponents/PlanarMechanics/examples/excavator/SoilContact.dyad"


def seed_required(environ=os.environ, shared: Path = SHARED) -> bool:
    """In CI, or beside the project's shared folder, a missing seed is a failure, not a skip."""
    return bool(environ.get("CI")) or shared.is_dir()


def _seed_source_block(text: str) -> str:
    lines = text.split("\n")
    start = lines.index("Source")
    opening = next(i for i in range(start, len(lines)) if lines[i] == "dyad")
    stop = lines.index("Flattened Source")
    block = lines[opening + 1:stop]
    while block and not block[-1].strip():
        block.pop()
    return "\n".join(block) + "\n"


def test_a_missing_seed_fails_in_ci_and_beside_the_shared_folder(tmp_path):
    assert seed_required({"CI": "true"}, tmp_path / "absent")
    assert seed_required({}, tmp_path)
    assert not seed_required({}, tmp_path / "absent")
    assert not seed_required({"CI": ""}, tmp_path / "absent")


def test_file_is_the_seed_source_byte_for_byte():
    if not SEED.exists():
        message = f"the seed text {SEED} is missing (expected in the shared folder beside the repository)"
        if seed_required():
            pytest.fail(message)
        pytest.skip(message)
    assert SOIL.read_bytes() == _seed_source_block(SEED.read_text(encoding="utf-8")).encode()


def test_file_ends_with_exactly_one_newline_after_end():
    data = SOIL.read_bytes()
    assert data.endswith(b"\nend\n") and not data.endswith(b"\n\n")


@pytest.fixture(scope="module")
def soil() -> ast.ComponentDef:
    file = parse_file(SOIL)
    assert len(file.definitions) == 1
    return file.definitions[0]


def test_structure(soil):
    assert soil.name == "SoilContact" and not soil.partial and soil.prefix is None
    kinds = [type(d).__name__ for d in soil.declarations]
    assert kinds.count("ParameterDecl") == 19
    assert kinds.count("VariableDecl") == 9
    assert kinds.count("ComponentDecl") == 2
    assert len(soil.relations) == 13
    assert sum(r.initial for r in soil.relations) == 1


def test_docstring_keeps_latex_verbatim(soil):
    assert soil.doc.startswith("\nSoil reaction force acting on a digging tool")
    assert r"F_y = A_{tip} \\left(\\frac{k_c}{b} + k_\\phi\\right) d^n - c_v d v_y" in soil.doc
    assert r"\\dot{m}_{load} = \\rho_{soil} \\, w" in soil.doc
    assert soil.doc.endswith("soil surface.\n")


def test_declarations(soil):
    by_name = {d.name: d for d in soil.declarations}
    assert by_name["gamma_s"].default == ast.Number(15700)
    assert by_name["k_c"].default == ast.Number(3e4)
    assert by_name["gamma_s"].doc == "Unit weight of the soil"
    assert by_name["y"].type == ast.TypeSpec("Length")
    assert by_name["g_vec"].type == ast.TypeSpec("Real", dims=(ast.Number(2),))
    frame = by_name["frame_a"]
    assert frame.type_name == "Frame2D" and frame.doc == "Frame of the digging tool tip"
    assert ast.metadata_dict(frame.metadata)["Dyad"]["placement"]["diagram"]["x2"] == 550
    slab = by_name["slab_shape"]
    assert slab.type_name == "MultibodyComponents.BoxShape"
    assert [m.name for m in slab.modifications][:3] == ["render", "color", "r"]
    (extends,) = soil.extends
    assert extends.type_name == "MultibodyComponents.Renderable"
    assert extends.modifications[0].name == "color"
    assert ast.metadata_dict(soil.metadata) == {
        "Dyad": {"icons": {"default": "dyad://MultibodyComponents/SoilContact.svg"}}}


def test_relations(soil):
    first = soil.relations[0]
    assert first == ast.Equation(ast.Ref((ast.RefPart("m_load"),)), ast.Number(0), initial=True)
    gravity = soil.relations[9]
    assert gravity.rhs == ast.Call("MultibodyComponents.PlanarMechanics.gravity_acceleration_2d")
    fx = soil.relations[10]
    assert fx.lhs == ast.Ref((ast.RefPart("frame_a"), ast.RefPart("fx")))
    product = fx.rhs.right               # -F_x - m_load * g_vec[1]
    assert product.right == ast.Ref((ast.RefPart("g_vec", (ast.Number(1),)),))


def test_spans_point_into_the_file(soil):
    assert (soil.span.line, soil.span.column) == (40, 11)   # its name, not the doc string on 1-39
    assert soil.declarations[0].span.line == 43      # `frame_a = ...`, not its doc string on 42
    der_equation = soil.relations[8]
    assert (der_equation.span.line, der_equation.span.column) == (120, 3)
    assert der_equation.lhs.span.end_column == 13      # `der(m_load)` ends at column 13
