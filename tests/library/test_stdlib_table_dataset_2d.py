"""DyadData's DyadInterpolationTable2D as the source of a two-dimensional table
(compiler/model/datasets_2d.py): a grid of the bilinear f(v, T) = 2 v + 3 T + v T / 10, read from
a file in each layout, is reproduced exactly by the bilinear table inside and beyond its axes, and
held along T by a constant dimension (model tests/models/Stdlib/DatasetTables2D.dyad); and its
located refusals."""
from __future__ import annotations

import numpy as np
import pytest

from compiler.errors import DyadError
from compiler.model.flatten import flatten_model
from tests.library.stdlib_support import Compiled

TEMPERATURES = np.array([0.0, 10.0, 20.0])


def bilinear(v, T):
    return 2 * v + 3 * T + v * T / 10


@pytest.fixture(scope="module")
def run():
    return Compiled().run("DatasetTables2D", 1.0, points=41)


def test_a_long_file_shuffled_gives_the_bilinear_function_everywhere(run):
    np.testing.assert_allclose(run["from_long.y"], bilinear(run["v"], run["T"]), atol=1e-9)


def test_a_matrix_file_held_along_the_second_axis(run):
    T = run["T"]
    inside = np.min(np.abs(T[:, None] - TEMPERATURES[None, :]), axis=1) > 1e-6    # off the knots
    held = TEMPERATURES[np.clip(np.searchsorted(TEMPERATURES, T, side="right") - 1, 0, 2)]
    np.testing.assert_allclose(run["from_matrix.y"][inside], bilinear(run["v"], held)[inside],
                               atol=1e-9)


def _rig(tmp_path, csv: str, part: str = "f") -> str:
    (tmp_path / "grid.csv").write_text(csv, encoding="utf-8")
    path = tmp_path / "Rig.dyad"
    path.write_text(
        "component Rig\n"
        "  structural parameter grid::DyadData.DyadInterpolationTable2D = DyadData."
        "DyadInterpolationTable2D(\"grid.csv\", axis1_name = \"a\", axis2_name = \"b\", "
        "data_name = \"f\")\n"
        "  table = BlockComponents.Tables.InterpolatedTable(axis1 = grid[\"a\"], axis2 = "
        f"grid[\"b\"], data = grid[\"{part}\"], interpolation_dim1 = BlockComponents.Tables."
        "InterpolationDimension.LinearInterpolationDimension(), interpolation_dim2 = "
        "BlockComponents.Tables.InterpolationDimension.LinearInterpolationDimension())\n"
        "relations\n  table.u1 = time\n  table.u2 = time\nend\n", encoding="utf-8")
    return str(path)


@pytest.mark.parametrize("csv, part, message, line", [
    ("a,b,f\n0,0,1\n0,1,2\n1,0,3\n", "f", "has no row for a = 1, b = 1", 2),
    ("a,b,f\n0,0,1\n0,0,2\n", "f", "a second row for a = 0, b = 0", None),
    ("x,y\n1,2\n", "f", "has neither columns named `a`, `b`, `f`", None),
    ("a,b,f\n0,0,1\n0,1,2\n1,0,3\n1,1,4\n", "g", "the table has no part `g`; it has `a`, `b`, `f`",
     3),
])
def test_bad_tables_are_located(tmp_path, csv, part, message, line):
    path = _rig(tmp_path, csv, part)
    with pytest.raises(DyadError) as err:
        flatten_model(f"{path}:Rig")
    assert message in err.value.message
    if line is not None:                         # at the declaration or the use in Rig.dyad
        assert (err.value.span.file, err.value.span.line) == (path, line)
    else:                                        # at the offending line of the data file
        assert err.value.span.file.endswith("grid.csv")


def test_a_dyad_uri_finds_the_file_in_the_package_assets_folder(tmp_path):
    package = tmp_path / "Grids"
    (package / "dyad").mkdir(parents=True)
    (package / "assets").mkdir()
    (package / "assets" / "grid.csv").write_text("a,b,f\n0,0,1\n0,1,2\n1,0,3\n1,1,4\n",
                                                 encoding="utf-8")
    (package / "dyad" / "Rig.dyad").write_text(
        "component Rig\n"
        "  structural parameter grid::DyadData.DyadInterpolationTable2D = DyadData."
        "DyadInterpolationTable2D(\"dyad://Grids/grid.csv\", axis1_name = \"a\", axis2_name = "
        "\"b\", data_name = \"f\")\n"
        "  table = BlockComponents.Tables.InterpolatedTable(axis1 = grid[\"a\"], axis2 = "
        "grid[\"b\"], data = grid[\"f\"], interpolation_dim1 = BlockComponents.Tables."
        "InterpolationDimension.LinearInterpolationDimension(), interpolation_dim2 = "
        "BlockComponents.Tables.InterpolationDimension.LinearInterpolationDimension())\n"
        "relations\n  table.u1 = 0.5\n  table.u2 = 0.25\nend\n", encoding="utf-8")
    from compiler.api import simulate
    result = simulate("Grids.Rig", stop=1.0, points=2, lib_dirs=(str(tmp_path),))
    assert result["table.y"][-1] == pytest.approx(1 + 2 * 0.5 + 0.25, abs=1e-12)   # 1 + 2a + b
