"""Sweep designs: axis text, grids as products, Latin-hypercube and random samples."""
import numpy as np
import pytest

from compiler.errors import DyadError
from compiler.sweep.design import (Axis, as_design, grid_design, parse_assignment, parse_axis,
                                   sampled_design)


def test_axis_forms():
    assert parse_axis("k", "1e5:1e6:10").values == tuple(np.linspace(1e5, 1e6, 10))
    assert parse_axis("m", "[800, 1200]").values == (800.0, 1200.0)
    assert parse_axis("m", "5").kind == "fixed" and parse_axis("m", "5").values == (5.0,)
    assert parse_axis("k", "1:3") == Axis("k", "uniform", (), 1.0, 3.0)
    assert parse_axis("k", "loguniform(1e3, 1e6)") == Axis("k", "loguniform", (), 1e3, 1e6)
    assert parse_axis("k", "normal(2, 0.5)") == Axis("k", "normal", (), 2.0, 0.5)
    assert parse_assignment("body.r[1]=[1,2]").name == "body.r[1]"


@pytest.mark.parametrize("text, says", [
    ("k", "write -p NAME=START:STOP:COUNT"),
    ("k=1:2:x", "is not a whole number"),
    ("k=1:2:0", "at least 1"),
    ("k=3:1", "is empty"),
    ("k=normal(1, 0)", "positive standard deviation"),
    ("k=loguniform(0, 1)", "positive bounds"),
    ("k=gamma(1, 2)", "unknown distribution"),
    ("k=[1, two]", "`two` is not a number"),
    ("k=1:2:3:4", "3 colons"),
    ("k=nan", "not a finite number"),
])
def test_bad_axes_say_what_is_wrong(text, says):
    with pytest.raises(DyadError, match=says):
        parse_assignment(text)


def test_grid_is_the_product_first_axis_slowest():
    design = grid_design([parse_axis("a", "[1, 2]"), parse_axis("b", "10:30:3"), parse_axis("c", "7")])
    assert design.names == ("a", "b")
    assert design.values.tolist() == [[1, 10], [1, 20], [1, 30], [2, 10], [2, 20], [2, 30]]
    assert design.sample(4) == {"c": 7.0, "a": 2.0, "b": 20.0}


def test_grid_refuses_ranges_and_empty_sweeps():
    with pytest.raises(DyadError, match="needs --samples"):
        grid_design([parse_axis("a", "1:2")])
    with pytest.raises(DyadError, match="nothing to sweep"):
        grid_design([parse_axis("a", "1")])
    with pytest.raises(DyadError, match="given twice"):
        grid_design([parse_axis("a", "[1,2]"), parse_axis("a", "[3]")])


def test_latin_hypercube_puts_one_sample_in_every_stratum():
    n = 40
    design = sampled_design([parse_axis("a", "0:1"), parse_axis("b", "10:20")], n, "lhs", seed=3)
    assert design.values.shape == (n, 2)
    for j, (low, high) in enumerate([(0, 1), (10, 20)]):
        strata = np.floor((design.values[:, j] - low) / (high - low) * n).astype(int)
        assert sorted(strata) == list(range(n))


def test_samples_are_reproducible_by_seed_and_follow_their_distribution():
    axes = [parse_axis("k", "loguniform(1e2, 1e4)"), parse_axis("m", "normal(5, 2)"),
            parse_axis("q", "[1, 2, 3]")]
    one = sampled_design(axes, 2000, "random", seed=11)
    assert np.array_equal(one.values, sampled_design(axes, 2000, "random", seed=11).values)
    assert not np.array_equal(one.values, sampled_design(axes, 2000, "random", seed=12).values)
    k, m, q = one.values.T
    assert 1e2 <= k.min() and k.max() <= 1e4
    assert abs(np.median(np.log10(k)) - 3.0) < 0.1             # uniform in the logarithm
    assert abs(m.mean() - 5) < 0.2 and abs(m.std() - 2) < 0.2
    assert set(q) == {1.0, 2.0, 3.0} and all(abs(np.mean(q == v) - 1 / 3) < 0.05 for v in (1, 2, 3))


def test_python_forms_of_a_design():
    assert as_design({"a": [1, 2], "b": [3, 4]}).values.shape == (4, 2)
    assert as_design({"a": "0:1"}, samples=5, seed=0).values.shape == (5, 1)
    listed = as_design([{"a": 1, "b": 2}, {"b": 5, "a": 4}])
    assert listed.names == ("a", "b") and listed.values.tolist() == [[1, 2], [4, 5]]
    with pytest.raises(DyadError, match="must set the same parameters"):
        as_design([{"a": 1}, {"b": 2}])
