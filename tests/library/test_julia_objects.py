"""A function called with a `path` connector field (a fluid medium, a Julia object) is kept as an
opaque function of its other arguments: `dyadc check` counts and matches the equations, and a run
refuses the model naming the function, instead of failing on how Julia would pick its method."""
from __future__ import annotations

import textwrap
from pathlib import Path

import pytest
import sympy

from compiler.api import simulate
from compiler.errors import DyadError
from compiler.model.flatten import flatten_model
from compiler.julia.objects import OpaqueJuliaCall, opaque_calls
from compiler.model.model_check import assess, require_standalone

# methods chosen by the medium's type: a call with an unknown medium never picks one, a call with
# a declared medium picks the one Julia would
JULIA = '''
abstract type Liquid end

@kwdef struct Water <: Liquid
  rho0 = 1000     # kg/m3
  beta = 2e9
end

Base.@kwdef struct Oil <: Liquid
  rho0 = 850
  beta = 1.5e9
  heavy = false
end

@kwdef struct Air
  rho0 = 1.2
end

function density(medium::Water, p)
  @unpack rho0, beta = medium
  return rho0 * (1 + p / beta)
end

function density(medium::Oil, p)
  @unpack rho0, beta, heavy = medium
  return ifelse(heavy, 2 * rho0, rho0) * (1 + p / beta)
end
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
  connect(source.port, tank.port)
end

component WaterPlant
  source = Source()
  tank = Tank()
  path medium::Medium = Water()
relations
  connect(source.port, tank.port)
  continuity(medium, source.port.medium)
end

component HeavyOilPlant
  source = Source()
  tank = Tank()
  path medium::Medium = Oil(heavy = true, beta = 1e9)
relations
  connect(source.port, tank.port)
  continuity(medium, source.port.medium)
end

component AirPlant
  source = Source()
  tank = Tank()
  path medium::Medium = Air()
relations
  connect(source.port, tank.port)
  continuity(medium, tank.port.medium)
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
    with pytest.raises(DyadError, match="`port.medium` is a Julia object"):
        flatten_model(f"{model}:ReadsTheMedium", [str(lib)])


@pytest.mark.parametrize("model, density_at", [
    ("WaterPlant", lambda p: 1000 * (1 + p / 2e9)),
    ("HeavyOilPlant", lambda p: 2 * 850 * (1 + p / 1e9)),       # fields given override defaults
])
def test_a_declared_medium_picks_the_method_of_its_type(project, model, density_at):
    path, lib = project
    result = simulate(f"{path}:{model}", stop=2.0, lib_dirs=[str(lib)], rtol=1e-9, atol=1e-9)
    for k in (0, -1):
        p = 1e5 + 1e4 * result.time[k]
        assert result["tank.rho"][k] == pytest.approx(density_at(p), rel=1e-12)
    # the tank's mass grows with the density: der(m) = volume * rho0' * 1e4 / beta
    assert result["tank.port.m_flow"][-1] == pytest.approx(
        2 * (density_at(1e5 + 1e4) - density_at(1e5)) / 1e4 * 1e4, rel=1e-6)


def test_a_medium_without_a_method_is_a_located_error(project):
    model, lib = project
    with pytest.raises(DyadError, match="`density` has no method for a medium of type `Air`"):
        flatten_model(f"{model}:AirPlant", [str(lib)])


LOOKUP = '''
type Table = Native
type Curve = func(::Real)::Real

component Lookup
  structural parameter table::Table
  final parameter curve::Curve = make_curve(table)
  variable u::Real
  variable y::Real
relations
  u = 2 * time
  y = curve(u)
end
'''


def test_a_native_or_function_typed_parameter_is_an_opaque_object(tmp_path):
    path = tmp_path / "lookup.dyad"
    path.write_text(LOOKUP, encoding="utf-8")
    flat = flatten_model(f"{path}:Lookup", [])
    calls = [a for e in flat.equations for a in e.residual.atoms(OpaqueJuliaCall)]
    assert [(type(c).__name__, c.args) for c in calls] == [("curve", (sympy.Symbol("u"),))]
    verdict = assess(flat)
    assert verdict.describe().startswith("balanced: 2 equations, 2 unknowns; dyadc cannot simulate")
    with pytest.raises(DyadError, match="calls function `curve` with a Julia object"):
        require_standalone(flat)


def test_an_array_argument_beside_a_julia_object_is_a_located_error(tmp_path):
    path = tmp_path / "lookup.dyad"
    path.write_text(LOOKUP.replace("y = curve(u)", "y = curve([u, u])"), encoding="utf-8")
    with pytest.raises(DyadError, match="`curve` with a Julia object takes scalar arguments") as info:
        flatten_model(f"{path}:Lookup", [])
    assert info.value.span is not None and info.value.span.line == 12
