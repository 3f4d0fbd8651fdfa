"""variants.dummy_choice reads a level's Jacobian from the selection outputs present in the values:
the same matrix as looking every possible entry up by its name (absent entries zero), also for
candidate names with brackets and commas, and with other outputs around."""
from __future__ import annotations

import numpy as np

from compiler.runtime import variants
from compiler.runtime.variants import dummy_choice, selection_output


def looked_up(levels, values, k, order):
    rows = int(levels[k]["rows"])
    return np.array([[float(values.get(selection_output(k, i, name), 0.0)) for name in order]
                     for i in range(rows)])


def test_the_level_matrix_is_the_one_every_name_looks_up(monkeypatch):
    rng = np.random.default_rng(3)
    names = ["der(der(x1))", "der(der(y1))", "a.b[1,2]", "der(q[3])", "w"]
    levels = [{"rows": 3, "order": names, "priority": {n: 0 for n in names}, "next": {}}]
    values = {"x1": 1.0, "__select": 5.0, "__selectx[1,a]": 7.0}
    for i in range(3):
        for name in names:
            if rng.random() < 0.6:
                values[selection_output(0, i, name)] = float(rng.standard_normal())
    seen = []
    monkeypatch.setattr(variants, "level_choice",
                        lambda matrix, priorities, rows, folds=(): seen.append(matrix.copy()) or list(range(rows)))
    assert dummy_choice(levels, values) == frozenset(names[:3])
    np.testing.assert_array_equal(seen[0], looked_up(levels, values, 0, names))
