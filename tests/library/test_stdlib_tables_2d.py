"""BlockComponents.Tables.InterpolatedTable, the two-dimensional table, against scipy's regular
grid interpolation and a hold computed by hand (model tests/models/Stdlib/Tables2D.dyad), and its
located refusals (compiler/model/table2d.py)."""
from __future__ import annotations

import numpy as np
import pytest

from compiler.errors import DyadError
from compiler.model.flatten import flatten_model
from tests.library.stdlib_support import Compiled

AXIS1 = np.array([0, 0.5, 1.2, 2])
AXIS2 = np.array([0, 10, 20])
DATA = AXIS1[:, None] ** 2 + AXIS1[:, None] * AXIS2[None, :] / 10


@pytest.fixture(scope="module")
def run():
    return Compiled().run("Tables2D", 2.0, points=201)


def _inputs(run):
    return run.time, 9 + 8 * np.sin(np.pi * run.time)


def test_the_data_literal_holds_the_samples():
    np.testing.assert_allclose(DATA, [[0, 0, 0], [0.25, 0.75, 1.25], [1.44, 2.64, 3.84], [4, 6, 8]])


def test_linear_in_both_axes_is_the_bilinear_table(run):
    from scipy.interpolate import RegularGridInterpolator
    u1, u2 = _inputs(run)
    expected = RegularGridInterpolator((AXIS1, AXIS2), DATA)(np.column_stack([u1, u2]))
    np.testing.assert_allclose(run["bilinear.y"], expected, atol=1e-9)


def test_hold_along_axis1_linear_along_axis2(run):
    u1, u2 = _inputs(run)
    inside = np.min(np.abs(u1[:, None] - AXIS1[None, :]), axis=1) > 1e-6    # away from the knots
    rows = np.clip(np.searchsorted(AXIS1, u1, side="right") - 1, 0, len(AXIS1) - 1)
    expected = np.array([np.interp(v, AXIS2, DATA[row]) for row, v in zip(rows, u2)])
    np.testing.assert_allclose(run["stepped.y"][inside], expected[inside], atol=1e-9)


@pytest.mark.parametrize("dims, data, message", [
    ("BSplineInterpolationDimension(2)", "[1 2; 3 4]",
         "`BSplineInterpolationDimension` is not supported by dyadc yet"),
    ("LinearInterpolationDimension()", "[1 2 3; 4 5 6]",
     "cannot interpolate the two-dimensional table: the data must have one row per point of axis1 "
     "and one column per point of axis2, 2 x 2, got 2 x 3"),
])
def test_bad_tables_are_located(tmp_path, dims, data, message):
    path = tmp_path / "Rig.dyad"
    path.write_text("component Rig\n  clock = BlockComponents.ContinuousClock()\n"
                    f"  table = BlockComponents.Tables.InterpolatedTable(axis1 = [0, 1], "
                    f"axis2 = [0, 1], data = {data}, "
                    f"interpolation_dim1 = BlockComponents.Tables.InterpolationDimension.{dims}, "
                    f"interpolation_dim2 = BlockComponents.Tables.InterpolationDimension.{dims})\n"
                    "relations\n  connect(clock.y, table.u1, table.u2)\nend\n")
    with pytest.raises(DyadError) as err:
        flatten_model(str(path))
    assert message in err.value.message
