"""The library search path (shipped library, -L DIR, DYADC_PATH) and which folders may run Python.

Issue 19.3: a `dyad_functions.py` planted beside a model file used to run on `dyadc check` and
`dyadc simulate`, because the model's folder was put on the library path. Plugins now run only
from the shipped library and from folders the user named (-L DIR, DYADC_PATH).
"""
from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from compiler.errors import DyadError
from compiler.model.flatten import flatten_model
from compiler.model.library import Library
from compiler.model.library_path import LIBRARY_PATH_VARIABLE, shipped_library_root

# der(x) = twice(1) with x(0) = 0: x(0.5) = 1 if and only if the plugin's `twice` was used.
USES_PLUGIN = """\
component Planted
  variable x::Real
relations
  initial x = 0
  der(x) = twice(1)
end
"""

PLUGIN = """\
from pathlib import Path

Path({marker!r}).write_text("the plugin ran")


def register(registry):
    registry.register("twice", lambda value: 2 * value, 1, 1)
"""


def _write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


@pytest.fixture
def planted(tmp_path):
    """A model folder with a dyad_functions.py that leaves a marker file when executed, and an
    empty working directory elsewhere."""
    folder, marker, work = tmp_path / "downloaded", tmp_path / "MARKER", tmp_path / "work"
    model = _write(folder / "Planted.dyad", USES_PLUGIN)
    _write(folder / "dyad_functions.py", PLUGIN.format(marker=str(marker)))
    work.mkdir()
    return model, marker, work


def _dyadc(*args, cwd: Path, env_path: str | None = None) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k != LIBRARY_PATH_VARIABLE}
    if env_path is not None:
        env[LIBRARY_PATH_VARIABLE] = env_path
    return subprocess.run([sys.executable, "-m", "compiler", *map(str, args)], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=300)


@pytest.mark.parametrize("command", [["check"], ["simulate", "--stop", "0.5"]])
def test_a_plugin_beside_a_model_file_is_not_run(planted, command):
    model, marker, work = planted
    run = _dyadc(command[0], model, *command[1:], cwd=work)
    assert not marker.exists(), "dyad_functions.py beside the model was executed"
    assert run.returncode == 1, run.stderr
    assert "Planted.dyad:5:12: error: unknown function `twice`" in run.stderr
    assert "dyad_functions.py was not run" in run.stderr and f"-L {model.parent}" in run.stderr
    assert "Traceback" not in run.stderr


def test_a_plugin_runs_when_its_folder_is_named_with_L(planted):
    model, marker, work = planted
    run = _dyadc("simulate", model, "--stop", "0.5", "-L", model.parent, cwd=work)
    assert run.returncode == 0, run.stderr
    assert marker.read_text() == "the plugin ran"
    final = dict(line.split() for line in run.stdout.splitlines())
    assert float(final["x"]) == pytest.approx(1.0, abs=1e-9)       # der(x) = twice(1) = 2


def test_a_plugin_runs_when_its_folder_is_on_DYADC_PATH(planted):
    model, marker, work = planted
    run = _dyadc("check", model, cwd=work, env_path=str(model.parent))
    assert run.returncode == 0, run.stderr
    assert marker.read_text() == "the plugin ran" and "balanced" in run.stdout


# ------------------------------------------------------------------ user libraries on the path

PROBE = """\
component Probe
  variable z::Real
relations
  z = {value}
end
"""

USER_MODEL = """\
component Rig
  probe = UserLib.Parts.Probe()
  variable y::Real
relations
  y = 2 * probe.z
end
"""


@pytest.fixture
def user_library(tmp_path):
    library = tmp_path / "userlib"
    _write(library / "UserLib" / "Parts" / "Probe.dyad", PROBE.format(value=3))
    _write(library / "UserLib" / "Rig.dyad", USER_MODEL)
    return library


def test_L_finds_a_user_component_from_another_working_directory(user_library, tmp_path):
    work = tmp_path / "work"
    work.mkdir()
    run = _dyadc("simulate", "UserLib.Rig", "--stop", "0.1", "-L", user_library, cwd=work)
    assert run.returncode == 0, run.stderr
    final = dict(line.split() for line in run.stdout.splitlines())
    assert float(final["y"]) == 6.0


def test_DYADC_PATH_finds_a_user_component(user_library, tmp_path):
    work = tmp_path / "work"
    work.mkdir()
    elsewhere = tmp_path / "missing-entries-are-skipped"
    run = _dyadc("check", "UserLib.Rig", cwd=work,
                 env_path=os.pathsep.join(["", str(elsewhere), str(user_library)]))
    assert run.returncode == 0, run.stderr
    assert "balanced" in run.stdout


def test_without_the_path_the_user_component_is_not_found(user_library, monkeypatch):
    monkeypatch.delenv(LIBRARY_PATH_VARIABLE, raising=False)
    with pytest.raises(DyadError) as caught:
        flatten_model("UserLib.Rig")
    assert "no model `UserLib.Rig` on the library path" in caught.value.message
    assert "-L DIR or DYADC_PATH" in caught.value.hint


def test_order_shipped_library_then_L_then_DYADC_PATH(tmp_path, monkeypatch):
    first, second = tmp_path / "first", tmp_path / "second"
    _write(first / "UserLib" / "Parts" / "Probe.dyad", PROBE.format(value=1))
    _write(second / "UserLib" / "Parts" / "Probe.dyad", PROBE.format(value=2))
    monkeypatch.setenv(LIBRARY_PATH_VARIABLE, str(second))
    library = Library([first])
    assert library.roots == [shipped_library_root(), first.resolve(), second.resolve()]
    assert [root.origin for root in library.search_path] == ["shipped library", "-L", "DYADC_PATH"]
    assert library.find("UserLib.Parts.Probe").file.span.file == str(first / "UserLib/Parts/Probe.dyad")
    # the base library Dyad is always the shipped one (a user package replaces any other: test_packages.py)
    shipped = library.find("Dyad.RealInput")
    assert Path(shipped.file.span.file).is_relative_to(shipped_library_root())
    _write(first / "Dyad" / "RealInput.dyad", "connector RealInput\n  potential v::Real\nend\n")
    assert Library([first]).find("Dyad.RealInput").file.span.file == shipped.file.span.file


def test_an_L_folder_that_does_not_exist_is_an_error(tmp_path):
    with pytest.raises(DyadError, match="given with -L\\) is not a directory"):
        Library([tmp_path / "nope"])


def test_the_shipped_library_comes_from_the_installed_package():
    import compiler.components
    assert shipped_library_root() == Path(compiler.components.__file__).resolve().parent
    assert (shipped_library_root() / "Dyad").is_dir()
