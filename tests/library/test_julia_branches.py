"""Julia helpers with branches, default arguments and chained comparisons are read (never run):
an `if`/`elseif`/`else` chain whose branches each return a value becomes a selection, an `if`
without `else` falls through to what follows, `lo < x < hi` means `lo < x && x < hi`, and a
trailing parameter with a default may be left out of a call."""
from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from compiler.api import simulate
from compiler.errors import DyadError
from compiler.model.flatten import flatten_model
from compiler.julia.functions import JuliaFunction, UnreadableFunction, read_julia_functions

SOURCE = '''
function band(x)
  if x <= 1
    return 10
  elseif 1 < x < 2
    return 20 + x
  else
    return 30
  end
end

function positive_part(x)
  if x > 0
    return x
  end
  return 0
end

function nested(x, y)
  if x > 0
    if y > 0
      return 1
    else
      return 2
    end
  else
    return 3
  end
end

scaled(x, k = 2, offset = k + 1) = k * x + offset

function branch_assigns(x)
  if x > 0
    y = x
  end
  return y
end

function no_else_at_end(x)
  if x > 0
    return x
  end
end

function default_first(a = 1, b)
  return a + b
end
'''


def _read(tmp_path: Path) -> dict:
    path = tmp_path / "helpers.jl"
    path.write_text(SOURCE, encoding="utf-8")
    return read_julia_functions(path, "Pkg")


def test_branches_defaults_and_chains_are_read(tmp_path):
    functions = _read(tmp_path)
    for name in ("band", "positive_part", "nested", "scaled"):
        assert isinstance(functions[f"Pkg.{name}"], JuliaFunction), functions[f"Pkg.{name}"]
    scaled = functions["Pkg.scaled"]
    assert scaled.parameters == ("x", "k", "offset")
    assert [name for name, _ in scaled.defaults] == ["k", "offset"]
    assert scaled.accepts(1) and scaled.accepts(3) and not scaled.accepts(0)
    assert not scaled.accepts(4) and scaled.arity() == "1 to 3"
    assert [name for name, _ in scaled.defaults_after(2)] == ["offset"]


@pytest.mark.parametrize("name, reason", [
    ("branch_assigns", "does not end in `return`"),
    ("no_else_at_end", "an `if` without `else` is its last statement"),
    ("default_first", "without a default follows one with a default"),
])
def test_forms_that_are_not_one_value_say_why(tmp_path, name, reason):
    found = _read(tmp_path)[f"Pkg.{name}"]
    assert isinstance(found, UnreadableFunction)
    assert reason in found.reason


def _project(tmp_path: Path, model: str) -> tuple[Path, Path]:
    project = tmp_path / "Pkg"
    (project / "dyad").mkdir(parents=True)
    (project / "src").mkdir()
    (project / "src" / "helpers.jl").write_text(SOURCE, encoding="utf-8")
    model_file = project / "dyad" / "Model.dyad"
    model_file.write_text(textwrap.dedent(model).lstrip(), encoding="utf-8")
    lib = tmp_path / "lib"
    lib.mkdir()
    (lib / "Pkg").symlink_to(project / "dyad", target_is_directory=True)
    return model_file, lib


def test_read_branches_give_the_values_of_the_julia_source(tmp_path):
    model, lib = _project(tmp_path, """
    component Model
      variable a::Real
      variable b::Real
      variable c::Real
      variable d::Real
      variable e::Real
      variable f::Real
      variable g::Real
    relations
      a = band(0.5)
      b = band(1.5)
      c = band(2.5)
      d = positive_part(-3) + positive_part(4)
      e = nested(1, -1) + 10 * nested(-1, 1)
      f = scaled(5)
      g = scaled(5, 3) + scaled(5, 3, 0)
    end
    """)
    result = simulate(f"{model}:Model", stop=1.0, lib_dirs=[str(lib)])
    expected = {"a": 10, "b": 21.5, "c": 30, "d": 4, "e": 2 + 30, "f": 2 * 5 + 3,
                "g": (3 * 5 + 4) + 3 * 5}
    for name, value in expected.items():
        assert result[name][-1] == pytest.approx(value), name


def test_a_branch_on_an_unknown_follows_it_over_time(tmp_path):
    model, lib = _project(tmp_path, """
    component Model
      variable x::Real
    relations
      initial x = 0
      der(x) = band(time)
    end
    """)
    result = simulate(f"{model}:Model", stop=3.0, lib_dirs=[str(lib)], rtol=1e-9, atol=1e-10)
    # integral of band over [0, 3]: 10*1 + (20*1 + (2^2 - 1^2)/2) + 30*1 = 61.5
    assert result["x"][-1] == pytest.approx(61.5, abs=1e-5)


def test_too_few_arguments_for_the_defaults_is_a_located_error(tmp_path):
    model, lib = _project(tmp_path, """
    component Model
      variable y::Real
    relations
      y = scaled()
    end
    """)
    with pytest.raises(DyadError, match=r"takes 1 to 3 argument\(s\), got 0"):
        flatten_model(f"{model}:Model", [str(lib)])
