"""An FMU of dyadc runs where neither dyadc, CasADi nor the compiler's Python is installed: a new
virtual environment with FMPy only (conftest.fresh_python) validates and simulates it."""
from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest

from compiler import api
from tests.fmu.conftest import MODELS

SCRIPT = """
import importlib.util, json, sys
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu
assert importlib.util.find_spec("compiler") is None and importlib.util.find_spec("casadi") is None
problems = validate_fmu(sys.argv[1])
result = simulate_fmu(sys.argv[1], stop_time=0.04, output=["vout"], relative_tolerance=1e-10,
                      output_interval=0.004)
print(json.dumps({"problems": problems, "time": result["time"].tolist(), "vout": result["vout"].tolist()}))
"""


@pytest.mark.parametrize("fmi", [2, 3])
def test_rectifier_fmu_in_an_environment_without_dyadc(exported, fresh_python, tmp_path, fmi):
    fmu = exported("Fmu.Rectifier", fmi=fmi)
    done = subprocess.run([str(fresh_python), "-c", SCRIPT, str(fmu)], capture_output=True, text=True,
                          timeout=300, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    found = json.loads(done.stdout.splitlines()[-1])
    assert found["problems"] == []
    grid = np.linspace(0.0, 0.04, 11)
    time, vout = np.array(found["time"]), np.array(found["vout"])
    keep = np.isin(time, grid) & np.concatenate([np.diff(time) > 0, [True]])
    own = api.simulate("Fmu.Rectifier", 0.04, lib_dirs=[MODELS], rtol=1e-10, atol=1e-10, saveat=time[keep])
    assert keep.sum() == 11
    assert np.max(np.abs(vout[keep] - own["vout"])) <= 1e-6 * 5.0
