"""FMUs of dyadc (FMI 2.0 and 3.0) validated and simulated by FMPy (another tool): no problems reported, and the
trajectories agree with dyadc's own run at the same tolerance (1e-10: both solvers' errors are
then far below the 1e-6 relative agreement asked; at 1e-8 each is ~1e-7 relative from the exact
solution of the step heater)."""
from __future__ import annotations

import math

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu


TOLERANCE = 1e-10


def _grid_rows(result, stop: float, points: int):
    """FMPy's rows on its output grid (it adds rows at events; those are left out)."""
    grid = np.linspace(0.0, stop, points)
    keep = np.isin(result["time"], grid) & np.concatenate([np.diff(result["time"]) > 0, [True]])
    return result[keep]


@pytest.mark.parametrize("model, variable, stop", [
    ("Fmu.RCCharge", "vout", 0.5),            # an RC circuit
    ("Fmu.Rectifier", "vout", 0.05),          # state events: the diode's condition
    ("Fmu.StepHeater", "T", 10.0),            # time events: the heater switched on and off
    ("Fmu.TwoBodies", "T_hot", 200.0),        # a thermal model with an algebraic unknown
    ("Fmu.SineSignal", "y", 1.0),             # no states at all
])
@pytest.mark.parametrize("fmi", [2, 3])
def test_fmpy_validates_and_matches_dyadc(exported, dyadc_run, model, variable, stop, fmi):
    fmu = exported(model, fmi=fmi)
    assert validate_fmu(str(fmu)) == []
    ran = simulate_fmu(str(fmu), stop_time=stop, output=[variable], relative_tolerance=TOLERANCE,
                       output_interval=stop / 100)
    rows = _grid_rows(ran, stop, 101)
    assert len(rows) == 101
    own = dyadc_run(model, stop, rows["time"], TOLERANCE)
    scale = np.max(np.abs(own[variable]))
    assert np.max(np.abs(rows[variable] - own[variable])) <= 1e-6 * scale


def test_rectifier_conducts_from_the_start(exported):
    """The diode's zero function is exactly 0 at t = 0 (a sine source): the FMU looks a step
    ahead to set the relation, so the first half wave charges the capacitor."""
    ran = simulate_fmu(str(exported("Fmu.Rectifier")), stop_time=0.005, output=["vout"],
                       relative_tolerance=TOLERANCE, output_interval=0.0005)
    assert ran["vout"][-1] > 4.5


@pytest.mark.parametrize("fmi", [2, 3])
def test_mass_spring_driven_through_its_input(exported, fmi):
    """The free input F is an FMU input: a step of F from 0 to 10 N at t = 0.5 s moves the mass
    as the closed-form response of m s'' + d s' + c s = F."""
    fmu = exported("Linear.MassSpringDamper", fmi=fmi)
    assert validate_fmu(str(fmu)) == []
    signal = np.array([(0.0, 0.0), (0.5, 0.0), (0.5, 10.0), (4.0, 10.0)], dtype=[("time", float), ("F", float)])
    ran = simulate_fmu(str(fmu), stop_time=4.0, input=signal, output=["mass.s"], relative_tolerance=TOLERANCE,
                       output_interval=0.04)
    rows = _grid_rows(ran, 4.0, 101)
    m, c, d, force = 2.0, 50.0, 3.0, 10.0
    omega, zeta = math.sqrt(c / m), d / (2 * math.sqrt(c * m))
    damped = omega * math.sqrt(1 - zeta ** 2)
    tau = np.clip(rows["time"] - 0.5, 0.0, None)
    exact = force / c * (1 - np.exp(-zeta * omega * tau) * (np.cos(damped * tau)
                                                             + zeta * omega / damped * np.sin(damped * tau)))
    assert np.max(np.abs(rows["mass.s"] - exact)) <= 1e-6 * force / c


def test_parameter_start_values_are_not_baked_in(exported):
    """-p V=5 is the start value of V in the FMU; an importer that sets V again gets its own."""
    fmu = exported("Fmu.RCCharge", V=5.0)
    tau = 100 * 1e-3
    given = simulate_fmu(str(fmu), stop_time=tau, output=["vout"], relative_tolerance=TOLERANCE)
    assert given["vout"][-1] == pytest.approx(5.0 * (1 - math.exp(-1.0)), rel=1e-7)
    changed = simulate_fmu(str(fmu), stop_time=tau, output=["vout"], relative_tolerance=TOLERANCE,
                           start_values={"V": 2.0, "R": 50.0})
    assert changed["vout"][-1] == pytest.approx(2.0 * (1 - math.exp(-2.0)), rel=1e-7)


EXCAVATOR = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"


@pytest.mark.parametrize("fmi", [2, 3])
def test_excavator_model_exchange(exported, dyadc_run, fmi):
    """The excavator's 12 s dig cycle (19 states, 3 algebraic unknowns, time events of its
    reference trajectory) integrated by FMPy's CVode at rtol 1e-9. The FMU's derivatives equal
    dyadc's to round-off (test_fmu_interface.py); the trajectories differ by CVode's error in the
    first stiff transient of the hydraulics (measured 4.8e-4 m at t = 0.12 s; it shrinks with
    CVode's tolerance: 3e-2 m at 1e-6), which the controllers then remove: at 12 s the bucket tip
    agrees to 1e-9 m (measured)."""
    fmu = exported(EXCAVATOR, fmi=fmi)
    assert validate_fmu(str(fmu)) == []
    ran = simulate_fmu(str(fmu), stop_time=12.0, output=["bucket.frame_b.x", "bucket.frame_b.y"],
                       relative_tolerance=1e-9, output_interval=0.12)
    rows = _grid_rows(ran, 12.0, 101)
    assert len(rows) == 101
    own = dyadc_run(EXCAVATOR, 12.0, rows["time"], lib_dirs=())
    for name in ("bucket.frame_b.x", "bucket.frame_b.y"):
        assert np.max(np.abs(rows[name] - own[name])) <= 1e-3
        assert abs(rows[name][-1] - own[name][-1]) <= 1e-7
