"""The FMU's C functions through FMPy's low-level API, FMI 2.0 and 3.0 (one C core behind both):
derivatives for any states set, directional derivatives equal to compiler/linear/elimination.py's
Jacobians (the one implementation), the FMU state saved and restored, serialized and read back in
another instance; and what modelDescription.xml says."""
from __future__ import annotations

import math
from ctypes import c_double

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Model, FMU2Slave
from fmpy.fmi3 import FMU3Model, FMU3Slave

from compiler import api
from compiler.linear.elimination import EliminatedSystem
from tests.fmu.conftest import MODELS


def _started(fmu, tmp_path, fmi: int = 2, kind: str = "me", name: str = "test", tolerance: float | None = None):
    """An instance initialized (and, for Model Exchange, in continuous-time mode), and the value
    references by name."""
    description = read_model_description(str(fmu))
    interface = description.modelExchange if kind == "me" else description.coSimulation
    classes = {(2, "me"): FMU2Model, (2, "cs"): FMU2Slave, (3, "me"): FMU3Model, (3, "cs"): FMU3Slave}
    instance = classes[fmi, kind](guid=description.guid, modelIdentifier=interface.modelIdentifier,
                                  unzipDirectory=extract(str(fmu), unzipdir=str(tmp_path / name)), instanceName=name)
    instance.instantiate()
    if fmi == 2:
        instance.setupExperiment(tolerance=tolerance, startTime=0.0)
        instance.enterInitializationMode()
    else:
        instance.enterInitializationMode(tolerance=tolerance, startTime=0.0)
    instance.exitInitializationMode()
    if kind == "me":
        instance.newDiscreteStates() if fmi == 2 else instance.updateDiscreteStates()
        instance.enterContinuousTimeMode()
    references = {v.name: v.valueReference for v in description.modelVariables}
    return instance, references


def _values(instance, references: list[int]) -> list[float]:
    return instance.getReal(references) if isinstance(instance, (FMU2Model, FMU2Slave)) else instance.getFloat64(references)


@pytest.mark.parametrize("fmi", [2, 3])
def test_derivatives_and_directional_derivatives_at_any_states(exported, tmp_path, fmi):
    """Two bodies with the temperature between their resistances algebraic: at states the FMU did
    not integrate to, der(x) and A = d der(x) / dx are those of EliminatedSystem (Newton on z), and
    FMI 3.0's adjoint derivatives are seed' A."""
    instance, refs = _started(exported("Fmu.TwoBodies", fmi=fmi), tmp_path, fmi)
    model = api.compile("Fmu.TwoBodies", lib_dirs=[MODELS]).model
    x = np.array([350.0, 310.0])
    instance.setTime(2.0)
    instance.setContinuousStates((c_double * len(x))(*x), len(x))
    buffer = (c_double * len(x))()
    (instance.getDerivatives if fmi == 2 else instance.getContinuousStateDerivatives)(buffer, len(x))
    derivatives = np.array(list(buffer))
    found = EliminatedSystem(model, [], []).evaluate(x, [], model.parameter_vector(), 2.0)
    assert derivatives == pytest.approx(found.derivatives, rel=1e-12)
    states = [refs[n] for n in model.state_names]
    rates = [refs[f"der({n})"] for n in model.state_names]
    for j in range(len(x)):
        column = instance.getDirectionalDerivative(rates, [states[j]], [1.0])
        assert column == pytest.approx(found.A[:, j], rel=1e-12)
    if fmi == 3:                     # the adjoint: seed' A, from the same elimination
        seed = [0.25, -2.0]
        assert instance.getAdjointDerivative(rates, states, seed) == pytest.approx(seed @ found.A, rel=1e-12)
    instance.terminate()
    instance.freeInstance()


@pytest.mark.parametrize("fmi", [2, 3])
def test_directional_derivatives_from_an_input(exported, tmp_path, fmi):
    """The mass on a spring-damper: d der(v) / dF = 1 / m, d der(v) / ds = -c / m."""
    instance, refs = _started(exported("Linear.MassSpringDamper", fmi=fmi), tmp_path, fmi)
    rate = [refs["der(mass.v)"]]
    assert instance.getDirectionalDerivative(rate, [refs["F"]], [1.0]) == pytest.approx([0.5], rel=1e-14)
    assert instance.getDirectionalDerivative(rate, [refs["mass.s"]], [1.0]) == pytest.approx([-25.0], rel=1e-14)
    instance.terminate()
    instance.freeInstance()


@pytest.mark.parametrize("fmi", [2, 3])
def test_fmu_state_saved_and_restored(exported, tmp_path, fmi):
    instance, refs = _started(exported("Fmu.RCCharge", fmi=fmi), tmp_path, fmi)
    saved = instance.getFMUState()
    instance.setTime(1.0)
    instance.setContinuousStates((c_double * 1)(7.0), 1)
    assert _values(instance, [refs["vout"]]) == [7.0]
    instance.setFMUState(saved)
    assert _values(instance, [refs["vout"]]) == [0.0]
    instance.freeFMUState(saved)
    instance.terminate()
    instance.freeInstance()


def _steps(instance, start: float, stop: float, reference: int) -> list[float]:
    values, time = [], start
    while time < stop - 1e-12:
        instance.doStep(time, 0.001)
        time += 0.001
        values.append(_values(instance, [reference])[0])
    return values


@pytest.mark.parametrize("fmi", [2, 3])
def test_serialized_state_continues_in_another_instance(exported, tmp_path, fmi):
    """The rectifier as Co-Simulation (its diode's relation lock and the integrator's step size
    are part of the state): stepped to 10 ms, its state serialized; a second instance, started
    afresh, reads the bytes back and steps on to 20 ms exactly as the first one did (bit for bit)."""
    fmu = exported("Fmu.Rectifier", kind="cs", fmi=fmi)
    first, refs = _started(fmu, tmp_path, fmi, "cs", "first")
    _steps(first, 0.0, 0.01, refs["vout"])
    state = first.getFMUState()
    serialized = first.serializeFMUState(state)
    first.freeFMUState(state)
    expected = _steps(first, 0.01, 0.02, refs["vout"])
    second, _ = _started(fmu, tmp_path, fmi, "cs", "second")
    state = second.deserializeFMUState(serialized)
    second.setFMUState(state)
    second.freeFMUState(state)
    assert _steps(second, 0.01, 0.02, refs["vout"]) == expected
    assert max(expected) > 4.0                                  # the diode conducted on the way
    with pytest.raises(FMICallException):                       # not a state's bytes: refused (and logged)
        second.deserializeFMUState(b"\x00" * len(serialized))
    other, _ = _started(exported("Fmu.Rectifier", fmi=fmi), tmp_path, fmi, "me", "other")
    with pytest.raises(FMICallException):                       # another FMU's state (its GUID differs)
        other.deserializeFMUState(serialized)
    other.freeInstance()
    for instance in (first, second):
        instance.terminate()
        instance.freeInstance()


@pytest.mark.parametrize("fmi", [2, 3])
def test_model_description(exported, fmi):
    description = read_model_description(str(exported("Linear.MassSpringDamper", fmi=fmi, m=4.0)))
    variables = {v.name: v for v in description.modelVariables}
    assert (variables["F"].causality, variables["F"].variability) == ("input", "continuous")
    assert (variables["m"].causality, variables["m"].variability, variables["m"].start) == ("parameter", "tunable", "4.0")
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


@pytest.mark.parametrize("fmi", [2, 3])
def test_event_indicators_and_outputs_described(exported, fmi):
    description = read_model_description(str(exported("Fmu.Rectifier", fmi=fmi)))
    assert description.numberOfEventIndicators == 1
    assert [u.variable.name for u in description.outputs] == []    # see docs/fmu.md: vout is a state
    description = read_model_description(str(exported("Fmu.StepHeater", fmi=fmi)))
    assert [u.variable.name for u in description.outputs] == ["T"]
    assert description.numberOfEventIndicators == 0


def test_fmi_3_time_and_event_indicators_are_variables(exported, tmp_path):
    """FMI 3.0 names the independent variable and gives each event indicator a value reference:
    reading it returns the zero function GetEventIndicators returns."""
    fmu = exported("Fmu.Rectifier", fmi=3)
    description = read_model_description(str(fmu))
    variables = {v.name: v for v in description.modelVariables}
    assert (variables["time"].causality, variables["time"].unit) == ("independent", "s")
    indicator = description.eventIndicators[0].variable
    assert (indicator.name, indicator.type) == ("__event_indicator[1]", "Float64")
    instance, refs = _started(fmu, tmp_path, 3)
    instance.setTime(0.0025)
    buffer = (c_double * 1)()
    instance.getEventIndicators(buffer, 1)
    assert instance.getFloat64([refs["__event_indicator[1]"], refs["time"]]) == [buffer[0], 0.0025]
    instance.terminate()
    instance.freeInstance()


def test_fmi_3_refuses_what_it_does_not_provide(exported, tmp_path, capsys):
    """Each refusal is an error status (or no instance) with a logged message: event mode in
    Co-Simulation, variables of a type the FMU has none of."""
    fmu = exported("Fmu.Rectifier", kind="cs", fmi=3)
    description = read_model_description(str(fmu))
    refused = FMU3Slave(guid=description.guid, modelIdentifier=description.coSimulation.modelIdentifier,
                        unzipDirectory=extract(str(fmu), unzipdir=str(tmp_path / "cs")), instanceName="events")
    with pytest.raises(Exception, match="Failed to instantiate"):
        refused.instantiate(eventModeUsed=True)
    assert "event mode in Co-Simulation is not provided (hasEventMode is false)" in capsys.readouterr().out
    instance, refs = _started(fmu, tmp_path, 3, "cs", "refusals")
    with pytest.raises(FMICallException):
        instance.getInt32([refs["vout"]])
    assert "this FMU has no Int32 variables" in capsys.readouterr().out
    instance.terminate()
    instance.freeInstance()


@pytest.mark.parametrize("fmi", [2, 3])
def test_tunable_parameter_changed_between_steps(exported, tmp_path, capsys, fmi):
    """The RC charge stepped to 0.2 s towards V = 10 V, then V tuned to 5 V: from there the
    capacitor relaxes to 5 V with the same time constant R C = 0.1 s (closed form). A Model
    Exchange instance refuses the change in continuous-time mode, with a logged message."""
    instance, refs = _started(exported("Fmu.RCCharge", kind="cs", fmi=fmi), tmp_path, fmi, "cs", tolerance=1e-10)
    set_values = instance.setReal if fmi == 2 else instance.setFloat64
    for k in range(20):
        instance.doStep(0.01 * k, 0.01)
    tuned = _values(instance, [refs["vout"]])[0]
    assert tuned == pytest.approx(10 * (1 - math.exp(-2.0)), rel=1e-6)
    set_values([refs["V"]], [5.0])
    for k in range(20, 60):
        instance.doStep(0.01 * k, 0.01)
    assert _values(instance, [refs["vout"]])[0] == pytest.approx(5 + (tuned - 5) * math.exp(-4.0), rel=1e-6)
    instance.terminate()
    instance.freeInstance()
    continuous, refs = _started(exported("Fmu.RCCharge", fmi=fmi), tmp_path, fmi, "me", "continuous")
    with pytest.raises(FMICallException):
        (continuous.setReal if fmi == 2 else continuous.setFloat64)([refs["V"]], [5.0])
    assert "a tunable parameter changes in event mode (Model Exchange) or between steps" in capsys.readouterr().out
    continuous.freeInstance()
