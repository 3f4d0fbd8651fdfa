"""Co-Simulation FMUs (`--kind cs`): the FMU integrates itself (TR-BDF2 with error control in
C, fmi2_cosimulation.inc) at the experiment's tolerance; FMPy validates and steps them, and they
agree with dyadc's run (rtol 1e-10) to a few hundred times the tolerance (TR-BDF2 is second
order; measured with FMPy's communication step of stop / 100)."""
from __future__ import annotations

import math

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.validation import validate_fmu


TOLERANCE = 1e-8


@pytest.mark.parametrize("model, variable, stop, allowed", [
    ("Fmu.RCCharge", "vout", 0.5, 1e-5),          # measured 5.7e-6 V of 10 V
    ("Fmu.Rectifier", "vout", 0.05, 5e-6),        # state events located inside the FMU: 7.2e-7 V
    ("Fmu.StepHeater", "T", 10.0, 5e-6),          # time events: 1.1e-6 K
    ("Fmu.TwoBodies", "T_hot", 200.0, 5e-4),      # 1.6e-4 K of 400 K
    ("Fmu.SineSignal", "y", 1.0, 1e-14),          # no states: nothing to integrate
])
@pytest.mark.parametrize("fmi", [2, 3])
def test_cosimulation_matches_dyadc(exported, dyadc_run, model, variable, stop, allowed, fmi):
    fmu = exported(model, kind="cs", fmi=fmi)
    assert validate_fmu(str(fmu)) == []
    assert read_model_description(str(fmu)).coSimulation is not None
    ran = simulate_fmu(str(fmu), stop_time=stop, output=[variable], relative_tolerance=TOLERANCE,
                       output_interval=stop / 100)
    own = dyadc_run(model, stop, ran["time"])
    assert np.max(np.abs(ran[variable] - own[variable])) <= allowed


def test_cosimulation_tolerance_is_the_experiments(exported):
    """A tighter tolerance, a smaller error: the RC charge at 1e-6 and at 1e-10."""
    fmu = exported("Fmu.RCCharge", kind="cs")
    exact = lambda t: 10.0 * (1 - np.exp(-t / 0.1))  # noqa: E731
    errors = []
    for tolerance in (1e-6, 1e-10):
        ran = simulate_fmu(str(fmu), stop_time=0.5, output=["vout"], relative_tolerance=tolerance,
                           output_interval=0.005)
        errors.append(np.max(np.abs(ran["vout"] - exact(ran["time"]))))
    assert errors[0] > 1e-5 and errors[1] < 1e-6


@pytest.mark.parametrize("fmi", [2, 3])
def test_cosimulation_driven_through_its_input(exported, fmi):
    fmu = exported("Linear.MassSpringDamper", kind="cs", fmi=fmi)
    signal = np.array([(0.0, 0.0), (0.5, 0.0), (0.5, 10.0), (4.0, 10.0)], dtype=[("time", float), ("F", float)])
    ran = simulate_fmu(str(fmu), stop_time=4.0, input=signal, output=["mass.s"], relative_tolerance=TOLERANCE,
                       output_interval=0.04)
    m, c, d, force = 2.0, 50.0, 3.0, 10.0
    omega, zeta = math.sqrt(c / m), d / (2 * math.sqrt(c * m))
    damped = omega * math.sqrt(1 - zeta ** 2)
    tau = np.clip(ran["time"] - 0.5, 0.0, None)
    exact = force / c * (1 - np.exp(-zeta * omega * tau) * (np.cos(damped * tau)
                                                             + zeta * omega / damped * np.sin(damped * tau)))
    assert np.max(np.abs(ran["mass.s"] - exact)) <= 1e-5        # measured 2.2e-6 m of 0.2 m


EXCAVATOR = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"


@pytest.mark.parametrize("fmi", [2, 3])
def test_excavator_cosimulation_within_1e_4_m_at_the_bucket_tip(exported, dyadc_run, fmi):
    """The excavator's 12 s dig cycle stepped by FMPy every 0.1 s, the FMU integrating itself at
    its default tolerance 1e-6: the bucket tip within 1e-4 m of dyadc's run at rtol 1e-10
    (measured 1.1e-5 m; 2.8e-6 m at 1e-7, 7.6e-7 m at 1e-8)."""
    fmu = exported(EXCAVATOR, kind="cs", fmi=fmi)
    assert validate_fmu(str(fmu)) == []
    ran = simulate_fmu(str(fmu), stop_time=12.0, output=["bucket.frame_b.x", "bucket.frame_b.y"],
                       output_interval=0.1)
    own = dyadc_run(EXCAVATOR, 12.0, ran["time"], lib_dirs=())
    for name in ("bucket.frame_b.x", "bucket.frame_b.y"):
        assert np.max(np.abs(ran[name] - own[name])) <= 1e-4
