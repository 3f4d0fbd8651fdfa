"""The message of a run that finds no regular state set (issue 16 item 2): it names the candidate
dummy derivatives, and each choice with the smallest singular value of its pivot block, best
first, so a user sees that every choice is singular and by how much."""
from __future__ import annotations

import re

import numpy as np

from compiler.runtime.switching import SETS_LISTED, singular_everywhere


def test_one_constraint_lists_each_candidate_with_its_pivot():
    # a rod constraint x^2 + y^2 = L^2 at the pivot itself: both derivatives 2x, 2y vanish
    level = {"rows": 1, "candidates": ["x", "y"], "chosen": [0], "classes": [[0, 1]], "entries": [0, 1]}
    text = singular_everywhere(level, np.array([2e-17, -6e-17]))
    assert "among x, y for the 1 constraint(s)" in text
    listed = re.findall(r"\{(\w+)\}: ([-+.\deE]+)", text)
    assert listed == [("y", "6e-17"), ("x", "2e-17")]       # best pivot first, magnitudes
    assert "largest entry of the constraints' Jacobian: 6e-17" in text


def test_two_constraints_give_the_smallest_singular_value_of_each_pair():
    # rank-one Jacobian (rows proportional): every 2x2 block is singular
    level = {"rows": 2, "candidates": ["a", "b", "c"], "chosen": [0, 1], "classes": [[0, 1, 2]],
             "entries": list(range(6))}
    matrix = np.array([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0]])
    text = singular_everywhere(level, matrix.reshape(-1))
    pairs = re.findall(r"\{(\w), (\w)\}: ([-+.\deE]+)", text)
    assert sorted((a, b) for a, b, _ in pairs) == [("a", "b"), ("a", "c"), ("b", "c")]
    assert all(float(value) < 1e-14 for _, _, value in pairs)


def test_many_choices_are_cut_short():
    names = [f"q{i}" for i in range(6)]
    level = {"rows": 2, "candidates": names, "chosen": [0, 1], "classes": [list(range(6))],
             "entries": list(range(12))}
    text = singular_everywhere(level, np.zeros(12))
    assert text.count("}:") == SETS_LISTED
    assert f"and {15 - SETS_LISTED} more" in text                   # C(6, 2) = 15 choices
