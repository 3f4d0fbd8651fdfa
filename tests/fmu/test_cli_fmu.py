"""`dyadc fmu`: the FMU written, -p with units, and what is refused (with located errors and
hints that run as printed)."""
from __future__ import annotations

import zipfile

from fmpy import read_model_description

from compiler.cli import main
from tests.fmu.conftest import MODELS


def fmu(*arguments: str) -> int:
    return main(["fmu", *arguments, "-L", MODELS])


def test_writes_binary_sources_and_description(tmp_path, capsys):
    path = tmp_path / "rc.fmu"
    assert fmu("Fmu.RCCharge", "-o", str(path), "-p", "C=2mF", "--stop", "0.5") == 0
    assert f"wrote {path}" in capsys.readouterr().err
    names = set(zipfile.ZipFile(path).namelist())
    assert {"modelDescription.xml", "binaries/linux64/RCCharge.so", "sources/fmi2_functions.c", "sources/fmu_model.c",
            "sources/dyfmu_functions.c", "sources/dyfmu_model.h"} <= names
    description = read_model_description(str(path))
    start = {v.name: v.start for v in description.modelVariables}
    assert start["C"] == "0.002" and description.defaultExperiment.stopTime == "0.5"


def test_fmi_3_writes_its_own_binary_folder_and_wrapper(tmp_path, capsys):
    path = tmp_path / "rc3.fmu"
    assert fmu("Fmu.RCCharge", "-o", str(path), "--fmi", "3", "--kind", "cs") == 0
    names = set(zipfile.ZipFile(path).namelist())
    assert {"binaries/x86_64-linux/RCCharge.so", "sources/fmi3_functions.c", "sources/fmu_model.c"} <= names
    assert "sources/fmi2_functions.c" not in names
    description = read_model_description(str(path))
    assert description.fmiVersion == "3.0" and description.coSimulation.canSerializeFMUstate


def test_other_fmi_versions_and_unknown_kinds_are_refused(tmp_path, capsys):
    path = str(tmp_path / "rc.fmu")
    assert fmu("Fmu.RCCharge", "-o", path, "--fmi", "1") == 1
    err = capsys.readouterr().err
    assert "error: --fmi 1: dyadc exports FMI 2.0 and 3.0 (FMI 1 is not an FMI version it writes)" in err
    assert "hint: give --fmi 2 or --fmi 3" in err
    assert fmu("Fmu.RCCharge", "-o", path, "--kind", "sc") == 1
    assert "error: --kind sc: an FMU is `me` (Model Exchange: the importer integrates) or `cs`" in capsys.readouterr().err
    assert not (tmp_path / "rc.fmu").exists()


def test_unknown_parameter_and_wrong_suffix(tmp_path, capsys):
    assert fmu("Fmu.RCCharge", "-o", str(tmp_path / "rc.fmu"), "-p", "Rx=3") == 1
    err = capsys.readouterr().err
    assert "error: -p: unknown parameter 'Rx' in model Fmu.RCCharge (did you mean 'R'?)" in err
    assert f"hint: its parameters: dyadc flatten Fmu.RCCharge -L {MODELS}" in err
    assert fmu("Fmu.RCCharge", "-o", str(tmp_path / "rc.zip")) == 1
    assert "an FMU is written as a .fmu file" in capsys.readouterr().err


def test_switching_state_set_is_refused_at_its_level(tmp_path, capsys):
    """The Cartesian pendulum changes its state set (x or y) as it swings: refused, located at the
    declaration of the level's first candidate."""
    assert fmu("Hard.CartesianPendulum", "-o", str(tmp_path / "p.fmu")) == 1
    err = capsys.readouterr().err
    assert "CartesianPendulum.dyad:19:3: error: `Hard.CartesianPendulum` switches its state set" in err
    assert "level 0 of its dummy-derivative choice: der(der(x)), der(der(y))" in err
    assert "Traceback" not in err
