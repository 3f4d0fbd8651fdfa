"""A function called with a `path` connector field (a fluid medium, a Julia object) is kept as an
opaque function of its other arguments: `dyadc check` counts and matches the equations, and a run
refuses the model naming the function, instead of failing on how Julia would pick its method."""
from __future__ import annotations

import textwrap
from pathlib import Path

import pytest
import sympy

from compiler.errors import DyadError
from compiler.model.flatten import flatten_model
from compiler.model.julia_objects import OpaqueJuliaCall, opaque_calls
from compiler.model.model_check import assess, require_standalone

# two methods chosen by the medium's type: dyadc never needs to pick one
JULIA = '''
struct Water end
struct Oil end
density(medium::Water, p) = 1000 + p / 1e6
density(medium::Oil, p) = 850 + p / 1e6
'''

DYAD = '''
type Medium = Native

connector Port
  potential p::Real
  flow m_flow::Real
  path medium::Medium
end

component Tank
  port = Port()
  parameter volume::Real = 2
  variable rho::Real
  variable m::Real
relations
  rho = density(port.medium, port.p)
  m = rho * volume
  port.m_flow = der(m)
end

component Source
  port = Port()
relations
  port.p = 1e5 + 1e4 * time
end

component Plant
  source = Source()
  tank = Tank()
relations
  initial tank.m = 2000
  connect(source.port, tank.port)
end

component ReadsTheMedium
  port = Port()
  variable y::Real
relations
  y = port.medium
  port.m_flow = 0
end
'''


@pytest.fixture
def project(tmp_path: Path) -> tuple[Path, Path]:
    root = tmp_path / "Fluids"
    (root / "dyad").mkdir(parents=True)
    (root / "src").mkdir()
    (root / "src" / "media.jl").write_text(JULIA, encoding="utf-8")
    model = root / "dyad" / "fluids.dyad"
    model.write_text(textwrap.dedent(DYAD).lstrip(), encoding="utf-8")
    lib = tmp_path / "lib"
    lib.mkdir()
    (lib / "Fluids").symlink_to(root / "dyad", target_is_directory=True)
    return model, lib


def test_a_call_with_a_medium_is_an_opaque_function_of_the_other_arguments(project):
    model, lib = project
    flat = flatten_model(f"{model}:Tank", [str(lib)])
    calls = [a for e in flat.equations for a in e.residual.atoms(OpaqueJuliaCall)]
    assert len(calls) == 1
    assert calls[0].args == (sympy.Symbol("port.p"),)
    assert opaque_calls(e.residual for e in flat.equations) == [type(calls[0]).__name__]
    assert type(calls[0]).__name__.endswith("density")


def test_check_counts_the_equations_and_says_it_cannot_run(project):
    model, lib = project
    verdict = assess(flatten_model(f"{model}:Plant", [str(lib)]))
    assert not verdict.is_partial and verdict.equations == verdict.unknowns
    line = verdict.describe()
    assert line.startswith("balanced:") and "dyadc cannot simulate it" in line
    assert "density" in line


def test_a_run_refuses_it_at_the_call(project):
    model, lib = project
    flat = flatten_model(f"{model}:Plant", [str(lib)])
    with pytest.raises(DyadError) as info:
        require_standalone(flat)
    assert "cannot be simulated by dyadc" in info.value.message
    assert "density" in info.value.message
    call_line = textwrap.dedent(DYAD).lstrip().splitlines().index("  rho = density(port.medium, port.p)")
    assert info.value.span is not None and info.value.span.line == call_line + 1


def test_reading_the_medium_as_a_number_is_still_an_error(project):
    model, lib = project
    with pytest.raises(DyadError, match="is a `path` field"):
        flatten_model(f"{model}:ReadsTheMedium", [str(lib)])
