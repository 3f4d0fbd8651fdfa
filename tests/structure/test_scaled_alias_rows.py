"""An equation multiplied through by a parameter (`k * der(x) = k * u`) is the same equation: the
state sets a run may switch between, and the alias rows the choice folds, may not change with it.
Until 2026-11-28 only unit coefficients counted as an alias row, so the scaled pendulum listed 3
state sets instead of 1 and Andrews' squeezer with two scaled velocity definitions switched state
sets six times in 0.01 s, 20x less accurate in its multipliers (metamorphic AndrewsSqueezer seed 0)."""
from __future__ import annotations

from pathlib import Path

import pytest

from compiler import api
from compiler.structure.state_selection.monitored import folded_levels, stand_in_pairs

PENDULUM = Path(__file__).resolve().parents[1] / "models" / "Hard" / "CartesianPendulum.dyad"


@pytest.fixture(scope="module")
def plain_and_scaled(tmp_path_factory):
    source = PENDULUM.read_text()
    scaled = source.replace("  der(x) = u\n  der(y) = v\n", "  k * der(x) = k * u\n  2 * der(y) = 2 * v\n") \
        .replace("  parameter theta0::Real = 0.5\n", "  parameter theta0::Real = 0.5\n  parameter k::Real = 0.001\n")
    assert scaled.count("k * der(x) = k * u") == 1 and "parameter k::Real" in scaled
    compiled = []
    for name, text in (("plain", source), ("scaled", scaled)):
        path = tmp_path_factory.mktemp(name) / PENDULUM.name
        path.write_text(text)
        compiled.append(api.compile(str(path)))
    return compiled


def _named(compilation, pairs):
    names = compilation.analysis.system.names
    return sorted((names[a], names[b]) for a, b in pairs)


def test_a_scaled_velocity_definition_is_a_stand_in_pair_as_written_plain(plain_and_scaled):
    plain, scaled = plain_and_scaled
    assert _named(scaled, stand_in_pairs(scaled.analysis.system)) == \
        [("der(u)", "der(der(x))"), ("der(v)", "der(der(y))")]
    assert _named(scaled, stand_in_pairs(scaled.analysis.system)) == _named(plain, stand_in_pairs(plain.analysis.system))


def test_a_scaled_model_lists_the_state_sets_and_folded_levels_of_the_plain_one(plain_and_scaled):
    plain, scaled = plain_and_scaled
    assert set(scaled.model.variants) == set(plain.model.variants)
    assert len(plain.model.variants) == 1

    def levels(c):
        names = c.analysis.system.names
        return [(len(rows), [names[v] for v in candidates], [names[v] for v in chosen])
                for rows, candidates, chosen in folded_levels(c.analysis, c.report)]
    assert levels(scaled) == levels(plain)
