"""BlockComponents' Boolean and Integer blocks (Logical, Sources, Math conversions) against their
truth tables, on a clock: a = t > 1 and b = t < 2.5 (model tests/models/Stdlib/BooleanBlocks.dyad)."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled


@pytest.fixture(scope="module")
def run():
    return Compiled().run("BooleanBlocks", 3.0, points=301)


def value(run, name, t):
    return run[name][int(np.argmin(np.abs(run.time - t)))]


# (t, a, b): the three phases of the two comparisons
PHASES = [(0.6, False, True), (1.8, True, True), (2.8, True, False)]


@pytest.mark.parametrize("t, a, b", PHASES)
def test_gates_follow_their_truth_tables(run, t, a, b):
    expected = {"above.y": a, "below.y": b, "both.y": a and b, "either.y": a or b,
                "one.y": a != b, "not_both.y": not (a and b), "neither.y": not (a or b),
                "inverted.y": not a}
    assert {name: bool(value(run, name, t)) for name in expected} == expected


@pytest.mark.parametrize("t, a, b", PHASES)
def test_switches_and_conversions(run, t, a, b):
    late = t >= 1.5                      # BooleanStep from true to false at 1.5
    assert bool(value(run, "late.y", t)) is (not late)
    assert bool(value(run, "picked.y", t)) is (True if b else not late)
    assert value(run, "chosen.y", t) == pytest.approx(t if a else -1.0, abs=1e-12)
    assert value(run, "as_real.y", t) == (5 if a and b else -5)
    assert value(run, "as_integer.y", t) == (7 if a != b else 3)


@pytest.mark.parametrize("t, count", [(0.5, -1), (1.9, -1), (2.1, 3), (3.0, 3)])
def test_integer_sources(run, t, count):
    assert value(run, "count.y", t) == count
    assert value(run, "counted.y", t) == count
    assert value(run, "fixed.y", t) == 6


@pytest.mark.parametrize("t, at_least, at_most, greater, less", [
    (0.3, False, True, False, True), (1.2, False, False, False, True), (2.4, True, False, True, False)])
def test_comparisons(run, t, at_least, at_most, greater, less):
    got = [bool(value(run, name, t)) for name in ("at_least.y", "at_most.y", "greater.y", "less.y")]
    assert got == [at_least, at_most, greater, less]
