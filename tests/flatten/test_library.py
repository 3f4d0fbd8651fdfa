"""Library path: lookup order, laziness, spec forms, DYADC_PATH, function plugins."""
from __future__ import annotations

import pytest

from compiler.errors import DyadError
from compiler.model.flatten import flatten_model
from compiler.model.functions import GLOBAL_REGISTRY, register_function
from compiler.model.library import Library
from compiler.model.model_spec import load_model


def test_resolving_a_model_parses_only_the_files_it_needs(sources):
    sources.write("Pkg/A.dyad", """
        component A
          b = B()
        end
    """)
    sources.write("Pkg/B.dyad", """
        component B
          variable x::Real
        relations
          x = 1
        end
    """)
    sources.write("Pkg/Unrelated.dyad", "this is not valid dyad at all (((")
    sources.write("Pkg/Shapes.dyad", """
        component Circle
          parameter r::Real = 1
        end
        component Square
          parameter a::Real = 1
        end
    """)
    library = Library([sources.root])
    lib, definition, qualified = load_model("Pkg.A", library=library)
    assert (definition.name, qualified) == ("A", "Pkg.A")
    from compiler.model.flatten import flatten_resolved
    from compiler.model.model_spec import resolve_model
    flat = flatten_resolved(resolve_model("Pkg.A", library), library)
    assert [v.name for v in flat.variables] == ["b.x"]
    assert library.parse_count == 2
    # a definition in a file not named after it: only that file is parsed
    assert library.find("Pkg.Square").definition.name == "Square"
    assert library.parse_count == 3
    assert library.find("Pkg.Missing") is None
    assert library.parse_count == 3


def test_lookup_order_local_then_enclosing_packages_then_standard(sources):
    sources.write("Outer/Thing.dyad", """
        component Thing
          variable outer_marker::Real
        relations
          outer_marker = 1
        end
    """)
    sources.write("Outer/Inner/Thing.dyad", """
        component Thing
          variable inner_marker::Real
        relations
          inner_marker = 2
        end
    """)
    sources.write("Outer/Inner/Deep/User.dyad", """
        component User
          t = Thing()
          variable s::Length
        relations
          s = t.inner_marker
        end
    """)
    flat = flatten_model("Outer.Inner.Deep.User", [str(sources.root)])
    names = [v.name for v in flat.variables]
    assert "t.inner_marker" in names            # innermost enclosing package wins
    assert flat.variable("s").units == "m"      # `Length` comes from the standard package Dyad


def test_using_imports_a_name(sources):
    sources.write("Lib/Tools/Spring.dyad", """
        component Spring
          variable f::Real
        relations
          f = 3
        end
    """)
    sources.write("App/Model.dyad", """
        using Lib.Tools: Spring
        component Model
          s = Spring()
        end
    """)
    flat = flatten_model("App.Model", [str(sources.root)])
    assert [v.name for v in flat.variables] == ["s.f"]


def test_spec_forms(sources):
    path = sources.write("Two.dyad", """
        partial component Base
          variable x::Real
        end
        component Two
          extends Base()
        relations
          x = 2
        end
        component Other
          variable y::Real
        relations
          y = 1
        end
    """)
    assert flatten_model(str(path)).name == "Two"           # named like the file
    assert flatten_model(f"{path}:Other").name == "Other"
    with pytest.raises(DyadError, match="no component `Nope`"):
        flatten_model(f"{path}:Nope")
    with pytest.raises(DyadError, match="no model `No.Such.Model`"):
        flatten_model("No.Such.Model")


def test_dyadc_path_environment_variable(sources, monkeypatch):
    sources.write("EnvPkg/Probe.dyad", """
        component Probe
          variable z::Real
        relations
          z = 4
        end
    """)
    monkeypatch.setenv("DYADC_PATH", str(sources.root))
    assert flatten_model("EnvPkg.Probe").variables[0].name == "z"


def test_function_plugin_in_a_library_folder(sources):
    sources.write("PluginPkg/dyad_functions.py", """
        def register(registry):
            registry.register("PluginPkg.triple", lambda x: 3 * x, 1, 1)
    """)
    sources.write("PluginPkg/UsesPlugin.dyad", """
        component UsesPlugin
          variable y::Real
        relations
          y = triple(2)
        end
    """)
    flat = flatten_model("PluginPkg.UsesPlugin", [str(sources.root)])
    assert str(flat.equations[0].residual) == "y - 6"
    assert GLOBAL_REGISTRY.get("PluginPkg.triple") is not None


def test_register_function_api(sources):
    register_function("TestFns.halve", lambda x: x / 2, 1, 1)
    flat = sources.flatten("""
        component Model
          variable y::Real
        relations
          y = TestFns.halve(8)
        end
    """)
    assert str(flat.equations[0].residual) == "y - 4"


def test_gravity_function_returns_the_world_vector(sources):
    flat = sources.flatten("""
        component Model
          variable g::Real[2]
        relations
          g = MultibodyComponents.PlanarMechanics.gravity_acceleration_2d()
        end
    """)
    assert [str(e.residual) for e in flat.equations] == ["g[1]", "g[2] + 9.80665"]
