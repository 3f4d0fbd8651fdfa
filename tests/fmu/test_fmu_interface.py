"""The FMU's C functions through FMPy's low-level API: derivatives for any states set, directional
derivatives equal to compiler/linear/elimination.py's Jacobians (the one implementation), the FMU
state saved and restored; and what modelDescription.xml says."""
from __future__ import annotations

from ctypes import c_double

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Model

from compiler import api
from compiler.linear.elimination import EliminatedSystem
from tests.fmu.conftest import MODELS


def _started(fmu, tmp_path):
    description = read_model_description(str(fmu))
    instance = FMU2Model(guid=description.guid, unzipDirectory=extract(str(fmu), unzipdir=str(tmp_path)),
                         modelIdentifier=description.modelExchange.modelIdentifier, instanceName="test")
    instance.instantiate()
    instance.setupExperiment(startTime=0.0)
    instance.enterInitializationMode()
    instance.exitInitializationMode()
    instance.newDiscreteStates()
    instance.enterContinuousTimeMode()
    references = {v.name: v.valueReference for v in description.modelVariables}
    return instance, references


def test_derivatives_and_directional_derivatives_at_any_states(exported, tmp_path):
    """Two bodies with the temperature between their resistances algebraic: at states the FMU did
    not integrate to, der(x) and A = d der(x) / dx are those of EliminatedSystem (Newton on z)."""
    instance, refs = _started(exported("Fmu.TwoBodies"), tmp_path)
    model = api.compile("Fmu.TwoBodies", lib_dirs=[MODELS]).model
    x = np.array([350.0, 310.0])
    instance.setTime(2.0)
    instance.setContinuousStates((c_double * len(x))(*x), len(x))
    buffer = (c_double * len(x))()
    instance.getDerivatives(buffer, len(x))
    derivatives = np.array(list(buffer))
    found = EliminatedSystem(model, [], []).evaluate(x, [], model.parameter_vector(), 2.0)
    assert derivatives == pytest.approx(found.derivatives, rel=1e-12)
    states = [refs[n] for n in model.state_names]
    rates = [refs[f"der({n})"] for n in model.state_names]
    for j in range(len(x)):
        column = instance.getDirectionalDerivative(rates, [states[j]], [1.0])
        assert column == pytest.approx(found.A[:, j], rel=1e-12)
    instance.terminate()
    instance.freeInstance()


def test_directional_derivatives_from_an_input(exported, tmp_path):
    """The mass on a spring-damper: d der(v) / dF = 1 / m, d der(v) / ds = -c / m."""
    instance, refs = _started(exported("Linear.MassSpringDamper"), tmp_path)
    rate = [refs["der(mass.v)"]]
    assert instance.getDirectionalDerivative(rate, [refs["F"]], [1.0]) == pytest.approx([0.5], rel=1e-14)
    assert instance.getDirectionalDerivative(rate, [refs["mass.s"]], [1.0]) == pytest.approx([-25.0], rel=1e-14)
    instance.terminate()
    instance.freeInstance()


def test_fmu_state_saved_and_restored(exported, tmp_path):
    instance, refs = _started(exported("Fmu.RCCharge"), tmp_path)
    saved = instance.getFMUState()
    instance.setTime(1.0)
    instance.setContinuousStates((c_double * 1)(7.0), 1)
    assert instance.getReal([refs["vout"]]) == [7.0]
    instance.setFMUState(saved)
    assert instance.getReal([refs["vout"]]) == [0.0]
    instance.freeFMUState(saved)
    instance.terminate()
    instance.freeInstance()


def test_model_description(exported):
    description = read_model_description(str(exported("Linear.MassSpringDamper", m=4.0)))
    variables = {v.name: v for v in description.modelVariables}
    assert (variables["F"].causality, variables["F"].variability) == ("input", "continuous")
    assert (variables["m"].causality, variables["m"].variability, variables["m"].start) == ("parameter", "fixed", "4.0")
    assert variables["mass.m"].causality == "parameter"         # bound to m, settable on its own
    assert variables["F"].description == "Force on the mass (left open: an input of the linearization)"
    assert variables["mass.s"].unit == "m" and variables["mass.v"].unit == "m/s"
    assert variables["der(mass.s)"].unit == "m/s" and variables["der(mass.v)"].unit == "m/s/s"
    units = {u.name: u for u in description.unitDefinitions}
    assert (units["N"].baseUnit.kg, units["N"].baseUnit.m, units["N"].baseUnit.s) == (1, 1, -2)
    assert variables["der(mass.v)"].derivative is variables["mass.v"]
    depends = {u.variable.name: sorted(d.name for d in u.dependencies)
               for u in description.derivatives}
    assert depends == {"der(mass.s)": ["mass.v"], "der(mass.v)": ["F", "mass.s", "mass.v"]}
    assert description.numberOfEventIndicators == 0


def test_event_indicators_and_outputs_described(exported):
    description = read_model_description(str(exported("Fmu.Rectifier")))
    assert description.numberOfEventIndicators == 1
    assert [u.variable.name for u in description.outputs] == []    # see docs/fmu.md: vout is a state
    description = read_model_description(str(exported("Fmu.StepHeater")))
    assert [u.variable.name for u in description.outputs] == ["T"]
    assert description.numberOfEventIndicators == 0
