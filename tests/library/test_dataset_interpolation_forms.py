"""Every form of `dataset_interpolation` Dyad's BlockComponents documentation uses, and DyadData's
dataset types as declared types (issue 27, item 3; compiler/model/interpolation_values.py,
structs.py): each one-dimensional form gives the chord of the same samples, y = 2 t on 0, 1, 2,
so y(1.5) = 3 exactly; a two-dimensional table given one-dimensional kinds is a located error
(the tables themselves: test_stdlib_tables_2d.py)."""
from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from compiler.api import simulate
from compiler.errors import DyadError
from compiler.model.flatten import flatten_model

SOURCE = """
type Dataset = Native
type Interpolant = func(::Real)::Real

component Forms
  structural parameter ds::Dataset = DyadDataset("d.csv", independent_var = "ts", dependent_vars = ["y"])
  structural parameter qualified::DyadData.DyadDataset = DyadData.DyadDataset("d.csv", independent_var = "ts", dependent_vars = ["y"])
  structural parameter series::DyadData.DyadTimeseries = DyadData.DyadTimeseries("d.csv", independent_var = "ts", dependent_vars = ["y"])
  final parameter whole::Interpolant = dataset_interpolation(LinearInterpolation, qualified)
  final parameter helpers::Interpolant = dataset_interpolation(LinearInterpolation, ds[only(get_dependent_vars(ds))], ds[get_independent_var(ds)])
  final parameter named::Interpolant = dataset_interpolation(LinearInterpolation, series["y"], series["ts"])
  final parameter file::Interpolant = dataset_interpolation(LinearInterpolation, "d.csv", "y", "ts")
  final parameter values::Interpolant = dataset_interpolation(LinearInterpolation, [0, 2, 4], [0, 1, 2])
  variable a::Real
  variable b::Real
  variable c::Real
  variable d::Real
  variable e::Real
relations
  a = whole(time)
  b = helpers(time)
  c = named(time)
  d = file(time)
  e = values(time)
end
"""


def project(tmp_path: Path, extra: str = "") -> Path:
    root = tmp_path / "Forms"
    (root / "dyad").mkdir(parents=True)
    (root / "dyad" / "Forms.dyad").write_text(SOURCE + textwrap.dedent(extra), encoding="utf-8")
    (root / "dyad" / "d.csv").write_text("ts,y\n0,0\n1,2\n2,4\n", encoding="utf-8")
    return root / "dyad" / "Forms.dyad"


def test_every_one_dimensional_form_interpolates_the_same_samples(tmp_path):
    path = project(tmp_path)
    result = simulate(f"{path}:Forms", stop=1.5, points=4)
    for name in "abcde":
        assert result[name][-1] == pytest.approx(3.0, abs=1e-12), name


def test_using_dyaddata_names_its_types_unqualified(tmp_path):
    path = project(tmp_path, """
    component Unqualified
      structural parameter s::DyadTimeseries
      variable x::Real
    relations
      x = 1
    end
    """)
    text = path.read_text(encoding="utf-8")
    path.write_text("using DyadData: DyadTimeseries\n" + text, encoding="utf-8")
    flat = flatten_model(f"{path}:Unqualified", [])
    assert [str(e.residual) for e in flat.equations] == ["x - 1"]


def test_without_using_an_unqualified_dyaddata_type_is_unknown(tmp_path):
    path = project(tmp_path, """
    component Unqualified
      structural parameter s::DyadTimeseries
    end
    """)
    with pytest.raises(DyadError) as info:
        flatten_model(f"{path}:Unqualified", [])
    assert "unknown type `DyadTimeseries`" in info.value.message
    assert info.value.span.line == SOURCE.count("\n") + 3


@pytest.mark.parametrize("call, message", [
    ("dataset_interpolation(LinearInterpolation, [0, 1], LinearInterpolation, [0, 1], ds)",
     "a two-dimensional table interpolates along each axis as a member of "
     "`BlockComponents.Tables.InterpolationDimension` says, not `LinearInterpolation`"),
    ("dataset_interpolation(LinearInterpolation, ds[\"z\"], ds[\"ts\"])",
     "the dataset has no column `z`; it has ts, y"),
    ("dataset_interpolation(LinearInterpolation, \"d.csv\", 1, \"ts\")",
     "the value column must be a string"),
    ("dataset_interpolation(LinearInterpolation, ds, ds, ds, ds, ds)",
     "got 6 arguments"),
    ("dataset_interpolation(LinearInterpolation, ds[\"y\"], ds[\"ts\"], 0)",
     "the fourth argument of `dataset_interpolation` is not a member of "
     "`BlockComponents.Tables.ExtrapolationType`"),
])
def test_bad_forms_are_located_at_the_call(tmp_path, call, message):
    path = project(tmp_path, f"""
    component Bad
      structural parameter ds::Dataset = DyadDataset("d.csv", independent_var = "ts", dependent_vars = ["y"])
      final parameter f::Interpolant = {call}
      variable a::Real
    relations
      a = f(time)
    end
    """)
    with pytest.raises(DyadError) as info:
        flatten_model(f"{path}:Bad", [])
    assert message in info.value.message
    assert info.value.span.line == SOURCE.count("\n") + 4
