"""Packages are units, as in Julia (issue 27.1): the first folder on the library path that holds
package P provides all of P; a user's package replaces a shipped one of the same name (a note names
both folders) and never merges with it; a user folder that only adds definitions to a shipped
package is a located error; names inside a package stay in it, its declared dependencies and the
base library `Dyad`."""
from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import warnings
from pathlib import Path

import pytest

from compiler.errors import DyadError
from compiler.model.flatten import flatten_model
from compiler.model.library import Library
from compiler.model.library_path import LIBRARY_PATH_VARIABLE, PackageNote, shipped_library_root

# The user's own TranslationalComponents, with a *component* named Position (a position source)
# beside a PartialRigid whose `s::Position` means the base library's type.
POSITION_SOURCE = """\
component Position
  flange = Flange()
  parameter s_ref::Dyad.Position = 0
relations
  flange.s = s_ref
end
"""

PARTIAL_RIGID = """\
partial component PartialRigid
  flange_a = Flange()
  flange_b = Flange()
  variable s::Position
relations
  flange_a.s = s
  flange_b.s = s
end
"""

# A block pushed by a constant force f: s = f t^2 / (2 m) from rest at 0.
BLOCK = """\
component Block
  extends PartialRigid
  parameter m::Dyad.Mass = {mass}
  variable v::Velocity
relations
  initial s = 0
  initial v = 0
  v = der(s)
  m * der(v) = flange_a.f + flange_b.f
end
"""

RIG = """\
component Rig
  block = TranslationalComponents.Block()
  pos = TranslationalComponents.Position(s_ref = 1)
  variable f::Dyad.Force
relations
  block.flange_a.f = -f
  f = 6
  block.flange_b.f = 0
end
"""


def _write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def _translational(library: Path, mass: float) -> Path:
    package = library / "TranslationalComponents"
    _write(package / "Position.dyad", POSITION_SOURCE)
    _write(package / "PartialRigid.dyad", PARTIAL_RIGID)
    _write(package / "Block.dyad", BLOCK.format(mass=mass))
    return package


@pytest.fixture
def two_libraries(tmp_path, monkeypatch):
    """Two user libraries that both define TranslationalComponents (Block of mass 2 and 3), and a
    Rig beside the first."""
    monkeypatch.delenv(LIBRARY_PATH_VARIABLE, raising=False)
    first, second = tmp_path / "first", tmp_path / "second"
    _translational(first, 2.0)
    _translational(second, 3.0)
    _write(second / "TranslationalComponents" / "OnlyInSecond.dyad", POSITION_SOURCE
           .replace("component Position", "component OnlyInSecond"))
    _write(first / "Rigs" / "Rig.dyad", RIG)
    return first, second


def _quiet_library(dirs) -> Library:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PackageNote)
        return Library(dirs)


def test_the_first_library_provides_the_whole_package(two_libraries):
    first, second = two_libraries
    library = _quiet_library([first, second])
    block = library.find("TranslationalComponents.Block")
    assert block.file.span.file == str(first / "TranslationalComponents" / "Block.dyad")
    # nothing of the second library's package, nor of the shipped one, is merged in
    assert library.find("TranslationalComponents.OnlyInSecond") is None
    assert library.find("TranslationalComponents.Spring") is None
    assert library.find("TranslationalComponents.PartialRigid").file.span.file == \
        str(first / "TranslationalComponents" / "PartialRigid.dyad")
    # in the other order, the second library's package is the one
    other = _quiet_library([second, first])
    assert other.find("TranslationalComponents.OnlyInSecond") is not None
    assert other.find("TranslationalComponents.Block").file.span.file == \
        str(second / "TranslationalComponents" / "Block.dyad")


def test_a_type_position_skips_the_packages_component_of_the_same_name(two_libraries):
    """`variable s::Position` in the user's PartialRigid is Dyad.Position, although the package
    holds a component Position (the published failure: "'Position' is a component, not a value
    type")."""
    first, second = two_libraries
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PackageNote)
        flat = flatten_model("Rigs.Rig", [first, second])
        swapped = flatten_model("Rigs.Rig", [second, first])
    assert flat.parameter_values()["block.m"] == 2.0          # the first library's Block
    assert swapped.parameter_values()["block.m"] == 3.0
    assert flat.variable("block.s").name == "block.s"


def test_the_replacement_note_names_both_folders(two_libraries):
    first, _ = two_libraries
    with pytest.warns(PackageNote) as caught:
        Library([first])
    messages = [str(w.message) for w in caught]
    shipped = shipped_library_root() / "TranslationalComponents"
    assert messages == [f"note: package `TranslationalComponents` from "
                        f"{first / 'TranslationalComponents'} replaces the shipped one in {shipped} "
                        f"(a package is found in one folder; nothing of the shipped one is used)"]


def test_a_user_folder_that_only_adds_to_a_shipped_package_is_a_located_error(tmp_path):
    added = _write(tmp_path / "lib" / "ElectricalComponents" / "TwoResistors.dyad",
                   "# two in series\ncomponent TwoResistors\n  r1 = Resistor(R = 1)\nend\n")
    with pytest.raises(DyadError) as caught:
        Library([tmp_path / "lib"])
    err = caught.value
    assert (err.span.file, err.span.line, err.span.column) == (str(added), 2, 11)
    assert "`TwoResistors` is added to package `ElectricalComponents`, which ships with dyadc" \
        in err.message
    assert f"move {tmp_path / 'lib' / 'ElectricalComponents'} to " \
           f"{tmp_path / 'lib' / 'MyElectricalComponents'}" in err.hint


def test_names_inside_a_package_stay_in_it_its_dependencies_and_the_base_library(tmp_path):
    library_folder = tmp_path / "lib"
    _write(library_folder / "Helper.dyad", "component Helper\n  variable h::Real\nrelations\n  h = 1\nend\n")
    _write(library_folder / "Mine" / "Project.toml",
           '[deps]\nElectricalComponents = "00000000-0000-0000-0000-000000000000"\n')
    _write(library_folder / "Mine" / "Uses.dyad", "component Uses\nend\n")
    library = Library([library_folder])
    file = library.find("Mine.Uses").file
    # a declared dependency, qualified, resolves; the base library too
    assert library.lookup("ElectricalComponents.Resistor", "Mine", file) is not None
    assert library.lookup("Pin", "Mine", file).qualified_name == "Dyad.Pin"
    # an undeclared package, an unqualified name of another package, a top-level file: never
    assert library.lookup("RotationalComponents.Inertia", "Mine", file) is None
    assert library.lookup("Resistor", "Mine", file) is None
    assert library.lookup("Helper", "Mine", file) is None
    # without a Project.toml a package may name any package on the path, qualified
    _write(library_folder / "Free" / "Uses.dyad", "component Uses\nend\n")
    free = library.find("Free.Uses").file
    assert library.lookup("RotationalComponents.Inertia", "Free", free) is not None
    assert library.lookup("Resistor", "Free", free) is None


def test_the_command_line_reports_the_added_folder_at_its_definition(tmp_path):
    added = _write(tmp_path / "lib" / "ElectricalComponents" / "TwoResistors.dyad",
                   "component TwoResistors\n  r1 = Resistor(R = 1)\nend\n")
    env = {k: v for k, v in os.environ.items() if k != LIBRARY_PATH_VARIABLE}
    run = subprocess.run([sys.executable, "-m", "compiler", "check", "ElectricalComponents.Resistor",
                          "-L", str(tmp_path / "lib")], cwd=tmp_path, env=env, capture_output=True,
                         text=True, timeout=300)
    assert run.returncode == 1
    assert run.stderr.startswith(f"{added}:1:11: error: `TwoResistors` is added to package "
                                 f"`ElectricalComponents`"), run.stderr
    assert "hint: make a package of your own" in run.stderr and "Traceback" not in run.stderr


def test_a_package_beside_a_model_file_replaces_the_shipped_one(two_libraries):
    """The folder of a model file given by path is the user's too: its TranslationalComponents is
    the one used, with the note."""
    first, _ = two_libraries
    model = _write(first / "Rig.dyad", RIG)
    with pytest.warns(PackageNote, match="from " + str(first / "TranslationalComponents")):
        flat = flatten_model(str(model))
    assert flat.parameter_values()["block.m"] == 2.0


def test_a_project_file_that_is_not_toml_is_a_located_error(tmp_path):
    project = _write(tmp_path / "lib" / "Mine" / "Project.toml", '[deps]\nElectricalComponents = \n')
    _write(tmp_path / "lib" / "Mine" / "Uses.dyad", "component Uses\nend\n")
    library = Library([tmp_path / "lib"])
    file = library.find("Mine.Uses").file
    with pytest.raises(DyadError) as caught:
        library.lookup("ElectricalComponents.Resistor", "Mine", file)
    assert (caught.value.span.file, caught.value.span.line) == (str(project), 2)
    assert caught.value.message.startswith("package `Mine` has a Project.toml that is not TOML: ")


def test_the_dyad_folder_of_a_julia_project_replaces_the_shipped_package(tmp_path):
    """A published library linked in as `lib/ElectricalComponents -> ElectricalComponents.jl/dyad`
    is a Julia package (its Project.toml is beside dyad/): it replaces ours, even when it only
    holds new names."""
    project = tmp_path / "ElectricalComponents.jl"
    _write(project / "Project.toml", 'name = "ElectricalComponents"\n')
    _write(project / "dyad" / "TwoResistors.dyad", "component TwoResistors\nend\n")
    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "ElectricalComponents").symlink_to(project / "dyad", target_is_directory=True)
    with pytest.warns(PackageNote, match="package `ElectricalComponents` from "):
        library = Library([tmp_path / "lib"])
    assert library.find("ElectricalComponents.TwoResistors") is not None
    assert library.find("ElectricalComponents.Resistor") is None
