"""The initialization starts an unknown that has no start value where an equation puts it, given
the values the others start at: an auxiliary `a = d[2]^2` under the cylinder mount's length
`L = sqrt(d[1]^2 + a)` started at 0 made L 0 and the unit vector `d / L` nan, and the run
stopped before its first step (metamorphic CylinderHoldingLoad, subcomponent seed 0, issue 25).
The library's mount is rewritten in a copy of its package (`-L` replaces the shipped one)."""
from __future__ import annotations

import shutil
import warnings
from pathlib import Path

import pytest

from compiler import api

ROOT = Path(__file__).resolve().parents[2]
MOUNT = "MultibodyComponents/PlanarMechanics/PlanarCylinderMount.dyad"


@pytest.fixture(scope="module")
def with_auxiliary(tmp_path_factory):
    library = tmp_path_factory.mktemp("lib")
    shutil.copytree(ROOT / "components" / "MultibodyComponents", library / "MultibodyComponents")
    path = library / MOUNT
    source = path.read_text()
    rewritten = source.replace("  L = sqrt(d[1] ^ 2 + d[2] ^ 2)\n", "  L = sqrt(d[1] ^ 2 + a)\n  a = d[2] ^ 2\n") \
        .replace("  variable e::Real[2]\n", "  variable e::Real[2]\n  variable a::Real\n")
    assert rewritten.count("a = d[2] ^ 2") == 1 and "variable a::Real" in rewritten
    path.write_text(rewritten)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")            # the note that the copy replaces the shipped package
        return api.compile(str(ROOT / "tests/models/ComponentTests/CylinderHoldingLoad.dyad"),
                           lib_dirs=(str(library), str(ROOT / "tests/models")))


def test_an_auxiliary_without_a_start_is_seeded_from_its_equation(with_auxiliary):
    assert with_auxiliary.reduced.initial.guesses["mount.a"] == pytest.approx(1.2 ** 2, rel=1e-15)
    assert "mount.a" not in with_auxiliary.reduced.initial.chosen       # a seed, not a condition


def test_the_mount_with_the_auxiliary_initializes_where_the_load_starts(with_auxiliary):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = api.simulate_compiled(with_auxiliary, 0.1, points=11, rtol=1e-8, atol=1e-8)
    assert result["load.r[2]"][0] == pytest.approx(1.2, abs=1e-12)
    assert result["mount.L"][0] == pytest.approx(1.2, abs=1e-12)
    assert result["mount.a"][0] == pytest.approx(1.44, abs=1e-12)
