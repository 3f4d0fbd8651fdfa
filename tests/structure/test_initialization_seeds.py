"""The initialization starts an unknown that has no start value where an equation puts it, given
the values the others start at: an auxiliary `a = d[2]^2` under the cylinder mount's length
`L = sqrt(d[1]^2 + a)` started at 0 made L 0 and the unit vector `d / L` nan, and the run
stopped before its first step (metamorphic CylinderHoldingLoad, subcomponent seed 0, issue 25).
The library's mount is rewritten in a copy of its package (`-L` replaces the shipped one).

Left to the compiler, the auxiliary is no state (the load's position is: the model differentiates
it, and the index reduction alone differentiates `a`); a state priority on `a` makes it one, and
then its start matters."""
from __future__ import annotations

import shutil
import warnings
from pathlib import Path

import pytest

from compiler import api

ROOT = Path(__file__).resolve().parents[2]
MOUNT = "MultibodyComponents/PlanarMechanics/PlanarCylinderMount.dyad"


def _compiled_with_auxiliary(library: Path, declaration: str):
    shutil.copytree(ROOT / "components" / "MultibodyComponents", library / "MultibodyComponents")
    path = library / MOUNT
    source = path.read_text()
    rewritten = source.replace("  L = sqrt(d[1] ^ 2 + d[2] ^ 2)\n", "  L = sqrt(d[1] ^ 2 + a)\n  a = d[2] ^ 2\n") \
        .replace("  variable e::Real[2]\n", f"  variable e::Real[2]\n  {declaration}\n")
    assert rewritten.count("a = d[2] ^ 2") == 1 and declaration in rewritten
    path.write_text(rewritten)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")            # the note that the copy replaces the shipped package
        return api.compile(str(ROOT / "tests/models/ComponentTests/CylinderHoldingLoad.dyad"),
                           lib_dirs=(str(library), str(ROOT / "tests/models")))


@pytest.fixture(scope="module")
def with_auxiliary(tmp_path_factory):
    """The auxiliary made a state by its priority."""
    return _compiled_with_auxiliary(tmp_path_factory.mktemp("lib"), "variable a::Real(state_priority = 1)")


def test_an_auxiliary_the_model_never_differentiates_is_no_state(tmp_path):
    """The compiler's first choice ranks candidates as the run-time choice does: the auxiliary's
    derivative is the dummy, the load's position and velocity stay states (it took the position's
    place, by name, when the pivoting met 1/sqrt(0) at the start: 11-16 tolerance units off the
    shipped mount's run, which is exact)."""
    compiled = _compiled_with_auxiliary(tmp_path, "variable a::Real")
    assert compiled.model.state_names == ["load.r[1]", "load.r[2]", "load.v[1]", "load.v[2]", "load.phi", "load.w"]
    # chosen by pivoting on every level, at the start completed by `a = d[2]^2` (not by names)
    assert len(compiled.report.pivot_conditions) == len(compiled.report.levels) == 2


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
