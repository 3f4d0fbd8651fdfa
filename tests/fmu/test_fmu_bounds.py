"""Declared min/max checked inside the FMU: the heater drawing 100 kW out of its body drives the
body's temperature below 0 K at t* = 1 + 25 ln(5000 / 4706.85) s (T = -4706.85 + 5000 e^(-(t-1)/25)
K after the switch at 1 s); the FMU stops there with an error status and a logged message naming
the variable, its value, its bound and the time, in both FMI versions (Model Exchange: at the
importer's completed step; Co-Simulation: at the FMU's own step)."""
from __future__ import annotations

import math
import re

import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException

CROSSING = 1 + 25 * math.log(5000 / 4706.85)


@pytest.mark.parametrize("fmi, kind", [(2, "me"), (3, "cs")])
def test_leaving_a_declared_bound_stops_with_a_logged_error(exported, capsys, fmi, kind):
    fmu = exported("Fmu.StepHeater", kind=kind, fmi=fmi, P=-1e5)
    variables = {v.name: v for v in read_model_description(str(fmu)).modelVariables}
    assert float(variables["body.T"].min) == 0.0
    with pytest.raises(FMICallException, match="CompletedIntegratorStep" if kind == "me" else "DoStep"):
        simulate_fmu(str(fmu), stop_time=10.0, relative_tolerance=1e-8, output_interval=0.01)
    logged = capsys.readouterr().out
    found = re.search(r"\[ERROR\] body\.T = (-[0-9.e-]+) is outside its declared min = 0: the model left its domain "
                      r"\(t = ([0-9.]+)\)", logged)
    assert found, logged
    assert CROSSING < float(found.group(2)) < CROSSING + 0.02
