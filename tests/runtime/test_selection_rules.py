"""The rules of the dummy-derivative choice that the compiler and the runtime share
(compiler/runtime/selection_rules.py), each on a worked example: the compiler calls them with
indices, the runtime with names, so both kinds of column are used here."""
from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from compiler.runtime.selection_rules import (folded_level, level_choice, may_degrade, next_candidates,
                                              preference_order, present_folds, priority_classes,
                                              propagating, stand_ins, watched_level)


def test_preference_puts_low_priority_then_more_differentiated_then_name_first():
    priority = {"der(w)": 0, "der(der(phi))": 0, "der(vx)": -1, "der(a)": 0}.__getitem__
    order = preference_order(["der(w)", "der(der(phi))", "der(vx)", "der(a)"], priority, str)
    assert order == ["der(vx)", "der(der(phi))", "der(a)", "der(w)"]


def test_priority_classes_group_positions_lowest_priority_first():
    assert priority_classes([3, -1, 3, 0, -1]) == [[1, 4], [3], [0, 2]]
    assert priority_classes([]) == []


@given(st.lists(st.integers(-3, 3), max_size=12))
def test_on_a_sorted_order_the_classes_are_its_runs_of_equal_priority(priorities):
    ordered = sorted(priorities)
    runs: list[list[int]] = []
    for j, value in enumerate(ordered):
        if j == 0 or value != ordered[j - 1]:
            runs.append([])
        runs[-1].append(j)
    assert priority_classes(ordered) == runs


def test_the_choice_on_a_level_takes_the_low_priority_class_first():
    # one row: the larger entry (column 2) is of higher priority, so column 0 is taken
    matrix = np.array([[0.5, 0.0, 3.0]])
    assert level_choice(matrix, [0, 0, 1], 1) == [0]
    assert level_choice(matrix, [1, 1, 0], 1) == [2]


def test_a_level_folded_drops_alias_rows_and_w_columns_and_keeps_u_with_its_w():
    folds = present_folds([(0, "ddx", "dvx"), (1, "ddy", "dvy")], ["ddx", "dvx", "ddy", "dlam"])
    assert folds == [(0, "ddx", "dvx")]                       # dvy is no candidate here
    folded = folded_level([0, 1, 2], ["ddx", "dvx", "ddy", "dlam"], ["ddx", "dvx", "dlam"], folds)
    assert (folded.rows, folded.candidates, folded.chosen) == ([1, 2], ["ddx", "ddy", "dlam"], ["ddx", "dlam"])
    alone = folded_level([0, 1, 2], ["ddx", "dvx", "ddy", "dlam"], ["ddx", "ddy"], folds)
    assert alone.chosen == ["ddy"]                            # ddx without dvx is no folded choice


def test_only_a_u_chosen_with_its_w_passes_to_the_next_level():
    partner = {"ddx": "dvx"}
    assert propagating(["ddx", "ddy"], partner) == ["ddy"]
    assert propagating(["ddx", "dvx"], partner) == ["ddx", "dvx"]
    assert next_candidates(["ddx", "dvx", "ddy"], partner, {"ddx": "dx", "ddy": "dy"}) == {"dx", "dy"}


def test_stand_ins_are_the_dummies_of_pairs_whose_first_is_kept():
    assert stand_ins([(4, 7), (5, 8)], kept=[5, 9]) == {8}


def test_a_level_may_degrade_only_with_room_a_varying_choice_and_no_hint_in_the_way():
    varies = {"a": True, "b": False, "c": True}.__getitem__
    flat = {"a": 0, "b": 0, "c": 0}
    assert may_degrade(1, ["a", "b", "c"], ["a"], flat, [], varies)
    assert not may_degrade(3, ["a", "b", "c"], ["a", "b", "c"], flat, [], varies)   # no other choice
    assert not may_degrade(1, ["a", "b", "c"], ["b"], flat, [], varies)             # constant block
    assert not may_degrade(1, ["a", "b", "c"], ["a"], flat, [("b", "a"), ("c", "a")], varies)  # stand-in
    hinted = {"a": 0, "b": 5, "c": 5}
    assert not may_degrade(1, ["a", "b", "c"], ["a"], hinted, [], varies)           # only hinted ones left


def test_the_watched_level_is_plain_data_with_its_classes():
    level = watched_level(1, ["der(x)", "der(y)"], [1], [2, -1], [7, 8])
    assert level == {"rows": 1, "candidates": ["der(x)", "der(y)"], "chosen": [1], "classes": [[1], [0]],
                     "entries": [7, 8]}
