"""Every library and test-model source parses, and every component documents itself and each of
its declarations (the docstrings feed `dyadc doc` and the error messages)."""
from __future__ import annotations

from pathlib import Path

import pytest

from compiler.syntax import parser
from compiler.syntax import ast  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
COMPONENTS = ROOT / "components"
SEED = COMPONENTS / "MultibodyComponents/PlanarMechanics/examples/excavator/SoilContact.dyad"
EXCAVATOR = COMPONENTS / "MultibodyComponents/PlanarMechanics/examples/excavator/Excavator.dyad"

# The standard package Dyad/ is checked by its own tests; the seed is copied verbatim.
LIBRARY_FILES = sorted(p for p in COMPONENTS.rglob("*.dyad")
                       if "Dyad" not in p.relative_to(COMPONENTS).parts[:1] and p != SEED)
MODEL_FILES = sorted((ROOT / "tests/models/ComponentTests").glob("*.dyad"))


def relative(path: Path) -> str:
    return str(path.relative_to(ROOT))


@pytest.mark.parametrize("path", LIBRARY_FILES + MODEL_FILES + [SEED], ids=relative)
def test_source_parses_to_one_definition_named_after_the_file(path):
    parsed = parser.parse_file(str(path))
    assert [d.name for d in parsed.definitions] == [path.stem]


@pytest.mark.parametrize("path", LIBRARY_FILES + MODEL_FILES, ids=relative)
def test_component_and_every_declaration_have_a_docstring(path):
    (definition,) = parser.parse_file(str(path)).definitions
    assert definition.doc and definition.doc.strip()
    undocumented = [d.name for d in getattr(definition, "declarations", ())   # a type has none
                    if not (d.doc and d.doc.strip())]
    assert not undocumented


def test_the_excavator_declares_the_dig_cycle_test_case():
    (definition,) = parser.parse_file(str(EXCAVATOR)).definitions
    case = ast.metadata_dict(definition.metadata)["Dyad"]["tests"]["dig_cycle"]
    assert case["stop"] == 12
    signals = case["expect"]["signals"]
    assert len(signals) == len(set(signals)) == 64
    assert set(case["atol"]) == set(signals)
    assert set(case["expect"]["final"]) <= set(signals)
    assert case["expect"]["final"]["soil.m_load"] > 100
