"""Runs on the native IDAS driver (compiler.runtime.native.make_integrator) against closed forms, the
excavator's golden trajectory and CasADi's IDAS: the same numbers within tolerance, events found
by IDAS's root finding (with direction) where sampling misses them, and CasADi's IDAS with a
warning where the native driver cannot run a model."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from compiler import api, runtime
from compiler.cache.c_code import compile_c
from compiler.runtime.native import NativeIdasWarning, library, make_integrator
from compiler.testing.golden import integrator_atol
from compiler.testing.golden_cases import discover
from compiler.testing.golden_compare import compare_signals, golden_path, read_golden, signal_values
from tests.runtime import runtime_systems as systems
from tests.runtime.lowered import compile_model

pytestmark = pytest.mark.skipif(library.driver_library()[0] is None,
                                reason="native IDAS driver not built (make install builds it)")
GOLDEN = Path(__file__).resolve().parents[1] / "golden"
EXCAVATOR = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"


def c_model(tmp_path, name: str, body: str):
    path = tmp_path / f"{name}.dyad"
    path.write_text(f"component {name}\n{body}\nend\n", encoding="utf-8")
    return compile_c(api.compile(str(path)).model)


def native(model, stop, **options):
    result = runtime.simulate(model, stop, integrator=make_integrator, **options)
    assert result.stats["integrator"] == "native"
    return result


def test_the_excavator_dig_cycle_matches_its_golden():
    (case,) = [c for c in discover() if c.model == EXCAVATOR]
    compilation = api.compile(EXCAVATOR)
    result = native(compile_c(compilation.model), case.stop, start=case.start, rtol=case.rtol,
                    atol=integrator_atol(compilation, case, case.rtol), points=case.points)
    checks, _ = compare_signals(case, result.time, signal_values(result, list(case.signals)),
                                read_golden(golden_path(GOLDEN, case)))
    assert len(checks) == 64 and [c.name for c in checks if not c.passed] == []
    assert max(c.ratio for c in checks) < 0.5         # well inside every tube


@pytest.mark.parametrize("reduced, stop, rtol", [
    (systems.robertson(), 40.0, 1e-8), (systems.pendulum_cartesian(0.9), 3.0, 1e-9),
    (systems.mass_chain(6), 2.0, 1e-9), (systems.rc_circuit(), 1.0, 1e-9)],
    ids=["robertson", "pendulum", "mass_chain", "rc"])
def test_the_same_numbers_as_casadi_idas(reduced, stop, rtol):
    model = compile_model(reduced, codegen="c")
    ours = native(model, stop, rtol=rtol, atol=rtol * 1e-2, points=51)
    theirs = runtime.simulate(model, stop, rtol=rtol, atol=rtol * 1e-2, points=51, integrator="casadi")
    assert theirs.stats["integrator"] == "casadi"
    # per signal, relative to its largest value; 1e-7 absolute for what is itself an error (the
    # pendulum's rod_error, the constraint's drift: 4e-8 on one path, 8e-9 on the other)
    scale = np.abs(theirs.values).max(axis=1, keepdims=True)
    assert np.all(np.abs(ours.values - theirs.values) <= 2e-5 * scale + 1e-7)


def test_a_bound_left_is_found_where_it_is_left():
    """x = 1 - t with min = 0: left at t = 1 (plus the bound's slack), warned of, run on."""
    model = compile_model(systems.draining(), codegen="c")
    with pytest.warns(UserWarning, match="left its declared min"):
        result = native(model, 2.0, rtol=1e-8, atol=1e-10, points=5)
    (left,) = result.stats["bounds_left"]
    assert left["time"] == pytest.approx(1.0, abs=1e-9)
    assert result["x"][-1] == pytest.approx(-1.0, abs=1e-9)


def test_a_model_without_c_code_runs_on_casadi_idas_with_a_warning():
    model = compile_model(systems.rc_circuit(), codegen="vm")     # CasADi's virtual machine
    with pytest.warns(NativeIdasWarning, match="no C library"):
        result = runtime.simulate(model, 0.1, points=3, integrator=make_integrator)
    assert result.stats["integrator"] == "casadi" and result["C.v"][-1] > 0


def test_the_switching_pendulum_against_its_closed_form():
    """Released at 2.3 rad it switches state sets 8 times in 5 s, each switch at the root of the
    degrading set's indicator; the bob within 3e-6 L of the closed form (1.4e-6 measured; CasADi's
    sampled path 1.1e-6, the angle ODE in one IDAS run at this rtol 5.8e-6 over 20 s)."""
    from tests.reference import pendulum
    theta0, length, g = 2.3, 0.8, 9.81
    compilation = api.compile("Hard.PendulumA01", lib_dirs=(str(Path(__file__).resolve().parents[1] / "models"),))
    result = native(compile_c(compilation.model), 5.0, rtol=1e-8, atol=1e-8, points=501,
                    params={"y0": -length * np.cos(theta0), "L": length, "g": g})
    exact = pendulum.solution(result.time, L=length, theta0=theta0, g=g)
    error = max(np.max(np.abs(result["x"] - exact["x"])), np.max(np.abs(result["y"] - exact["y"])))
    assert error / length < 3e-6
    assert len(result.stats["state_switches"]) == 8


def test_the_command_line_runs_the_native_driver(tmp_path, capsys):
    from compiler.cli import main
    spec = tmp_path / "Leaves.dyad"
    spec.write_text("component Leaves\n  variable x::Real\n  variable y::Real\nrelations\n"
                    "  initial x = 0\n  initial y = 0\n  der(x) = -1\n"
                    "  der(y) = if x < 0 then 1.0 else 0.0\nend\n", encoding="utf-8")
    assert main(["simulate", str(spec), "--stop", "2", "--codegen", "c", "--no-cache",
                 "--integrator", "native"]) == 0
    printed = capsys.readouterr()
    assert "1 event" in printed.err and "warning" not in printed.err
    assert [line.split() for line in printed.out.splitlines()][-1] == ["y", "2"]


def test_andrews_squeezer_matches_the_test_set():
    """The Test Set's Andrews' squeezer at t = 0.03, rtol 1e-10 (tests/hard/test_andrews_squeezer.py
    on CasADi's IDAS): angles 3.3e-10, rates 5.7e-8 relative measured (CasADi 7.6e-11, 2.9e-8)."""
    from tests.hard.conftest import compile_hard
    from tests.reference import andrews
    result = native(compile_c(compile_hard("AndrewsSqueezerAccelerations").model), andrews.T_END,
                    points=31, rtol=1e-10, atol=1e-10)
    angles = np.array([result[name][-1] for name in andrews.ANGLE_NAMES])
    rates = np.array([result[name][-1] for name in ("bep", "thp", "gap", "php", "dep", "omp", "epp")])
    assert np.max(np.abs(angles / andrews.REFERENCE_ANGLES - 1)) < 1e-8
    assert np.max(np.abs(rates / andrews.REFERENCE_RATES - 1)) < 1e-6


def test_ctrl_c_stops_a_long_native_call(tmp_path):
    """A call to the stop runs in C: SIGINT (Ctrl-C) is looked at after every IDAS step and ends
    the run as an interrupt, as on CasADi's IDAS (tests/cli/test_interrupt.py), not at the stop."""
    import os
    import signal
    import threading
    import time
    model = c_model(tmp_path, "Forced", """
  variable x::Real
  variable y::Real
relations
  initial x = 1
  initial y = 0
  der(x) = y
  der(y) = -x + sin(1000 * time)""")
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    began = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(runtime.SimulationInterrupted, match="interrupted"):
            runtime.simulate(model, 1000.0, rtol=1e-10, atol=1e-12, points=1001,
                             integrator=make_integrator)
    finally:
        timer.cancel()
    assert time.perf_counter() - began < 10.0


def test_without_the_driver_library_runs_use_casadi_idas_and_say_why(monkeypatch):
    monkeypatch.setattr(library, "driver_library", lambda: (None, "the native IDAS driver is not built"))
    model = compile_model(systems.rc_circuit(), codegen="c")
    with pytest.warns(NativeIdasWarning, match="the native IDAS driver is not built"):
        result = runtime.simulate(model, 0.1, points=3, integrator=make_integrator)
    assert result.stats["integrator"] == "casadi"


def test_an_archive_with_another_checksum_is_refused(tmp_path):
    from compiler.native import build
    fake = tmp_path / "amici-1.1.0.tar.gz"
    fake.write_bytes(b"not the sdist")
    with pytest.raises(RuntimeError, match=f"expected {build.ARCHIVE_SHA256}"):
        build.fetch_archive(tmp_path, fake)


def test_a_failure_is_reported_as_on_casadi_idas():
    """0 = z^2 + t - 1 has no solution past t = 1: the same flag, explanation and time."""
    model = compile_model(systems.vanishing_root(), codegen="c")
    messages = []
    for integrator in (None, make_integrator):
        with pytest.raises(runtime.SimulationFailed) as failed:
            runtime.simulate(model, 2.0, integrator=integrator)
        messages.append(str(failed.value))
    assert messages[0] == messages[1]
    assert "failed at t = 1: IDA_CONV_FAIL" in messages[1]


def test_a_state_set_chosen_among_several_rows_switches_natively():
    """The Test Set's transistor amplifier: a level of 6 rows whose indicator only proposes a
    switch; the pivot quality is judged at the end of each IDAS step while it proposes one, and IDAS
    steps on without a restart where the chosen set still serves. The same 38 switches as on
    CasADi's sampled path, the eight node voltages to 6 digits of the Test Set's reference at
    t = 0.2 (8.4 .. 13.4 measured on either path)."""
    from tests.hard.test_test_set_formulations import TRANSAMP, TRANSAMP_REFERENCE
    model = compile_c(api.compile(str(TRANSAMP)).model)
    assert max(int(level["rows"]) for level in model.state_sets) == 6
    result = native(model, 0.2, points=201, rtol=1e-10, atol=1e-10)
    assert len(result.stats["state_switches"]) == 38
    computed = np.array([result[f"y{i}"][-1] for i in range(1, 9)])
    assert np.all(np.abs(computed / TRANSAMP_REFERENCE - 1) < 1e-6)


def test_the_transistor_amplifier_runs_natively_below_rtol_1e_11():
    """After its first state-set switch (t = 0.0118) the run integrates at rtol 5e-14, where
    der(y7)'s round-off exceeded the Newton test's weight: IDA_CONV_FAIL at t = 0.0131 at
    rtol 1.1e-12 (and 5e-13, 1.25e-12) before the algebraic unknowns' Newton weights had a floor
    (integrator.NEWTON_ATOL_FLOOR)."""
    from tests.hard.test_test_set_formulations import TRANSAMP
    model = compile_c(api.compile(str(TRANSAMP)).model)
    result = native(model, 0.02, points=41, rtol=1.1e-12, atol=1.1e-12)
    assert result.time[-1] == 0.02 and len(result.stats["state_switches"]) == 2
