"""Functions a Dyad project defines in Julia (`Project/src/*.jl` beside `Project/dyad/`) are read,
never run: assignments and one returned expression are inlined at the call; anything else is a
located error that says why."""
from __future__ import annotations

import textwrap
from pathlib import Path

import pytest
import sympy

from compiler.api import simulate
from compiler.errors import DyadError
from compiler.model.flatten import flatten_model
from compiler.julia.functions import JuliaFunction, UnreadableFunction, read_julia_functions

HELPERS = '''
"""
    celsius_to_kelvin(c)

A docstring with a function word inside: function f(x) end
"""
function celsius_to_kelvin(c)
  k = c + 273.15   # a local
  return k
end

twice(x::Real) = 2 * x

function clip(x, lo, hi)
  return(
    ifelse((x > hi) & (hi > lo), hi,
      ifelse(x < lo | false, lo, x))
  )
end

function uses_block(x)
  while x > 0
    x = x - 1
  end
  return x
end

function uses_global(x)
  return x * some_global
end

function forever(x)
  return forever(x)
end
'''


def _project(tmp_path: Path, model: str) -> tuple[Path, Path]:
    """A Dyad project MyLib (dyad/ and src/) and a library folder linking MyLib to its dyad/."""
    project = tmp_path / "MyLib"
    (project / "dyad").mkdir(parents=True)
    (project / "src").mkdir()
    (project / "src" / "helpers.jl").write_text(HELPERS, encoding="utf-8")
    model_file = project / "dyad" / "Model.dyad"
    model_file.write_text(textwrap.dedent(model).lstrip(), encoding="utf-8")
    lib = tmp_path / "lib"
    lib.mkdir()
    (lib / "MyLib").symlink_to(project / "dyad", target_is_directory=True)
    return model_file, lib


def test_reader_keeps_readable_functions_and_says_why_others_are_not(tmp_path):
    path = tmp_path / "helpers.jl"
    path.write_text(HELPERS, encoding="utf-8")
    functions = read_julia_functions(path, "MyLib")
    assert set(functions) == {"MyLib.celsius_to_kelvin", "MyLib.twice", "MyLib.clip",
                              "MyLib.uses_block", "MyLib.uses_global", "MyLib.forever"}
    assert isinstance(functions["MyLib.celsius_to_kelvin"], JuliaFunction)
    assert functions["MyLib.celsius_to_kelvin"].parameters == ("c",)
    assert functions["MyLib.twice"].parameters == ("x",)
    assert functions["MyLib.celsius_to_kelvin"].line == 7
    assert "uses `while`" in functions["MyLib.uses_block"].reason
    assert "some_global" in functions["MyLib.uses_global"].reason
    assert isinstance(functions["MyLib.uses_global"], UnreadableFunction)


def test_qualified_and_unqualified_calls_are_inlined(tmp_path):
    model, lib = _project(tmp_path, """
    component Model
      variable t::Real
      variable d::Real
      variable c::Real
    relations
      t = MyLib.celsius_to_kelvin(20)
      d = twice(t)
      c = clip(time, 0.5, 2)
    end
    """)
    for spec, dirs in ((f"{model}:Model", [str(lib)]), ("MyLib.Model", [str(lib)])):
        flat = flatten_model(spec, dirs)
        by_name = {str(sorted(e.residual.free_symbols, key=str)): e.residual for e in flat.equations}
        t, d = sympy.Symbol("t"), sympy.Symbol("d")
        assert float(by_name["[t]"].subs(t, 293.15)) == pytest.approx(0)
        assert float(by_name["[d, t]"].subs({t: 1, d: 2})) == pytest.approx(0)


def test_inlined_function_simulates(tmp_path):
    model, lib = _project(tmp_path, """
    component Model
      variable c::Real
      variable x::Real
    relations
      initial x = 0
      c = clip(time, 0.5, 2)
      der(x) = c
    end
    """)
    result = simulate(f"{model}:Model", stop=3.0, lib_dirs=[str(lib)], rtol=1e-8, atol=1e-10)
    # integral of clip(t, 0.5, 2) over [0, 3]: 0.5*0.5 + (2^2 - 0.5^2)/2 + 2*1 = 4.125
    assert result["x"][-1] == pytest.approx(4.125, abs=1e-5)


_RECURSIVE_CALL_LINE = HELPERS.splitlines().index("  return forever(x)") + 1


@pytest.mark.parametrize("call, message, where", [
    ("uses_block(1)", "cannot read: it uses `while`", ("Model.dyad", 4)),
    ("uses_global(1)", "`some_global`, which is neither a parameter nor a local", ("Model.dyad", 4)),
    ("forever(1)", "calls itself more than", ("helpers.jl", _RECURSIVE_CALL_LINE)),
    ("twice(1, 2)", "takes 1 argument(s), got 2", ("Model.dyad", 4)),
])
def test_unusable_functions_are_located_errors(tmp_path, call, message, where):
    model, lib = _project(tmp_path, f"""
    component Model
      variable y::Real
    relations
      y = {call}
    end
    """)
    with pytest.raises(DyadError) as info:
        flatten_model(f"{model}:Model", [str(lib)])
    assert message in info.value.message
    span = info.value.span
    assert span is not None and (Path(span.file).name, span.line) == where


def test_a_dyad_folder_without_julia_sources_still_reports_an_unknown_function(tmp_path):
    model, lib = _project(tmp_path, """
    component Model
      variable y::Real
    relations
      y = not_defined_anywhere(1)
    end
    """)
    with pytest.raises(DyadError, match="unknown function `not_defined_anywhere`"):
        flatten_model(f"{model}:Model", [str(lib)])


def test_comprehension_variables_are_bound_only_inside_their_comprehension(tmp_path):
    path = tmp_path / "arrays.jl"
    path.write_text("squares(n) = [k^2 for k in 1:n]\n"
                    "table(a, n) = [a[min(j, k)] for j in 1:n, k in 1:n]\n"
                    "leaks(n) = sum([k for k in 1:n]) + k\n", encoding="utf-8")
    functions = read_julia_functions(path, "MyLib")
    assert isinstance(functions["MyLib.squares"], JuliaFunction)
    assert isinstance(functions["MyLib.table"], JuliaFunction)
    assert isinstance(functions["MyLib.leaks"], UnreadableFunction)
    assert "it uses `k`" in functions["MyLib.leaks"].reason
