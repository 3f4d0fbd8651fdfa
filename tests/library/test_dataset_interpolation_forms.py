"""Every form of `dataset_interpolation` Dyad's BlockComponents documentation uses, and DyadData's
dataset types as declared types (issue 27, item 3; compiler/model/interpolation_values.py,
structs.py): each one-dimensional form gives the chord of the same samples, y = 2 t on 0, 1, 2,
so y(1.5) = 3 exactly; the two-dimensional table is a located refusal."""
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
     "a two-dimensional table"),
    ("dataset_interpolation(LinearInterpolation, ds[\"z\"], ds[\"ts\"])",
     "the dataset has no column `z`; it has ts, y"),
    ("dataset_interpolation(LinearInterpolation, \"d.csv\", 1, \"ts\")",
     "the value column must be a string"),
    ("dataset_interpolation(LinearInterpolation, ds, ds, ds, ds, ds)",
     "got 6 arguments"),
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


EXTRAPOLATED = """
component Outside
  final parameter held::Interpolant = dataset_interpolation(QuadraticInterpolation, [0, 1, 4], [0, 1, 2], ExtrapolationType.Constant())
  final parameter tangent::Interpolant = dataset_interpolation(QuadraticInterpolation, [0, 1, 4], [0, 1, 2], ExtrapolationType.Linear)
  final parameter extended::Interpolant = dataset_interpolation(QuadraticInterpolation, [0, 1, 4], [0, 1, 2], DataInterpolations.ExtrapolationType.Extension())
  final parameter thrown::Interpolant = dataset_interpolation(QuadraticInterpolation, [0, 1, 4], [0, 1, 2], ExtrapolationType.None())
  variable a::Real
  variable b::Real
  variable c::Real
  variable d::Real
  variable e::Real
relations
  a = held(3 * time)
  b = tangent(3 * time)
  c = extended(3 * time)
  d = thrown(3 * time)
  e = held(-time)
end
"""


def test_the_extrapolation_argument_sets_the_values_outside_the_samples(tmp_path):
    """Dyad's newer Tables.Interpolation passes DataInterpolations' ExtrapolationType as a fourth
    argument. The samples lie on x^2, so the quadratic is x^2 inside; at x = 3: held at the last
    sample 4, along the end tangent 4 + 4 * 1 = 8, continued 9 (also for `None`, read as
    `Extension`); at x = -1 held at the first sample 0."""
    path = project(tmp_path, EXTRAPOLATED)
    result = simulate(f"{path}:Outside", stop=1.0, points=3)
    finals = {name: result[name][-1] for name in "abcde"}
    assert finals == pytest.approx({"a": 4.0, "b": 8.0, "c": 9.0, "d": 9.0, "e": 0.0}, abs=1e-9)


@pytest.mark.parametrize("member, message", [
    ("Periodic", "`ExtrapolationType.Periodic` is not supported by dyadc yet"),
    ("Sideways", "`ExtrapolationType` has no member `Sideways`; it has None, Extension, Constant, "
                 "Linear, Periodic, Reflective"),
])
def test_an_unsupported_or_unknown_extrapolation_is_located(tmp_path, member, message):
    path = project(tmp_path, f"""
    component Bad
      final parameter f::Interpolant = dataset_interpolation(LinearInterpolation, [0, 1], [0, 1], ExtrapolationType.{member}())
      variable a::Real
    relations
      a = f(time)
    end
    """)
    with pytest.raises(DyadError) as info:
        flatten_model(f"{path}:Bad", [])
    assert info.value.message == message
    assert (info.value.span.line, info.value.span.column) == (SOURCE.count("\n") + 3, 95)


def test_the_extrapolation_may_be_a_parameter_given_by_the_user_of_the_component(tmp_path):
    """As Tables.Interpolation declares it: a parameter holding the ExtrapolationType, with a
    default, overridden where the component is used. The chord through (0, 0), (1, 2) at x = 3:
    held 2 by default, 6 along the line when given Linear."""
    path = project(tmp_path, """
    component Table
      structural parameter extrapolation_type::Native = ExtrapolationType.Constant()
      final parameter f::Interpolant = dataset_interpolation(LinearInterpolation, [0, 2], [0, 1], extrapolation_type)
      variable a::Real
    relations
      a = f(2 + time)
    end
    component Tables
      held = Table()
      along = Table(extrapolation_type = ExtrapolationType.Linear())
    end
    """)
    result = simulate(f"{path}:Tables", stop=1.0, points=3)
    assert (result["held.a"][-1], result["along.a"][-1]) == pytest.approx((2.0, 6.0), abs=1e-9)
