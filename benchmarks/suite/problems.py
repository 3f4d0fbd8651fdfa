"""The five work-precision problems: model, output grid, reference solution and error measures.

Every contender delivers named signals on the problem's output grid; `errors(signals)` turns
them into named error measures, of which "error" is the one plotted and matched for speed-ups.
"""
from __future__ import annotations

import importlib.util
import sys
import time
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Callable

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
CONTENDERS = ROOT / "benchmarks" / "contenders"
MODELS = ROOT / "tests" / "models" / "Benchmarks"


def load_path(name: str, path: Path):
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def contender_module(name: str):
    if str(CONTENDERS) not in sys.path:
        sys.path.insert(0, str(CONTENDERS))
    return load_path(f"_bench_{name}", CONTENDERS / f"{name}.py")


def reference_module(name: str):
    return contender_module("_reference_loader").load_reference(name)


@dataclass
class Problem:
    key: str
    title: str
    dyadc_spec: str
    stop: float
    grid: np.ndarray
    scipy_module: str
    scipy_options: dict
    error_label: str
    atol_ratio: float = 1.0          # atol = atol_ratio * rtol for every contender
    dyadc_lib_dirs: tuple[str, ...] = ()
    notes: list[str] = field(default_factory=list)

    def dyadc_signals(self, result) -> dict[str, np.ndarray]:
        return {name: np.asarray(result[name]) for name in self.signal_names()}

    def signal_names(self) -> list[str]:
        raise NotImplementedError

    def scipy_signals(self, output: dict) -> dict[str, np.ndarray]:
        return output["signals"]

    def errors(self, signals: dict[str, np.ndarray]) -> dict[str, float]:
        raise NotImplementedError


class Pendulum(Problem):
    THETA0, T_END, POINTS = 0.5, 100.0, 1001

    def __init__(self):
        super().__init__(
            key="pendulum", title="Index-3 Cartesian pendulum, theta0 = 0.5 rad, t = 0 ... 100 s",
            dyadc_spec=str(MODELS / "CartesianPendulum.dyad"), stop=self.T_END,
            grid=np.linspace(0.0, self.T_END, self.POINTS), scipy_module="scipy_pendulum",
            scipy_options={"theta0": self.THETA0, "t_end": self.T_END, "points": self.POINTS},
            error_label="max over the grid of |theta - theta_exact| [rad]",
            notes=["dyadc integrates the index-3 DAE in x, y, u, v, T (index reduction by the compiler, "
                   "states x and u); scipy integrates the hand-reduced angle ODE (2 states, exact Jacobian).",
                   "theta = atan2(x, -y) for dyadc; reference: the closed form (Jacobi elliptic functions)."])

    def signal_names(self):
        return ["x", "y"]

    def dyadc_signals(self, result):
        return {"theta": np.arctan2(np.asarray(result["x"]), -np.asarray(result["y"]))}

    def errors(self, signals):
        exact = reference_module("pendulum").solution(self.grid, theta0=self.THETA0)["theta"]
        return {"error": float(np.max(np.abs(signals["theta"] - exact)))}


class SwingingPendulum(Pendulum):
    """Released above the horizontal: no static state choice holds, dyadc switches states."""
    THETA0, T_END, POINTS = 2.0, 10.0, 1001

    def __init__(self):
        Problem.__init__(
            self, key="swinging", title="Index-3 Cartesian pendulum with state switching, theta0 = 2.0 rad, "
                                        "t = 0 ... 10 s",
            dyadc_spec="StructureModels.CartesianPendulumHigh",
            dyadc_lib_dirs=(str(ROOT / "tests" / "structure" / "models"),), stop=self.T_END,
            grid=np.linspace(0.0, self.T_END, self.POINTS), scipy_module="scipy_pendulum",
            scipy_options={"theta0": self.THETA0, "t_end": self.T_END, "points": self.POINTS},
            error_label="max over the grid of |theta - theta_exact| [rad]",
            notes=["The same DAE without state hints, released 2.0 rad from the downward vertical: every "
                   "swing passes the horizontal, where x cannot be a state, and the bottom, where y cannot. "
                   "dyadc switches between (x, u) and (y, v) about 15 times in 10 s; scipy integrates the "
                   "angle ODE, which never needs a switch.",
                   "theta = atan2(x, -y) for dyadc; reference: the closed form (Jacobi elliptic functions)."])


class Andrews(Problem):
    def __init__(self):
        andrews = reference_module("andrews")
        super().__init__(
            key="andrews", title="Andrews' squeezing mechanism (index 3), t = 0 ... 0.03",
            dyadc_spec=str(MODELS / "Andrews.dyad"), stop=andrews.T_END,
            grid=np.linspace(0.0, andrews.T_END, 31), scipy_module="scipy_andrews",
            scipy_options={"points": 31},
            error_label="max relative error of the 7 angles at t = 0.03",
            notes=["dyadc integrates the Test Set's index-3 DAE (7 angles, 7 rates, 6 multipliers) "
                   "written as equations; scipy integrates the hand-derived index-1 ODE "
                   "(KKT solve per call, complex-step Jacobian).",
                   "Reference: the Test Set's solution at t = 0.03 (PSIDE, rtol = atol = 1e-14)."])

    def signal_names(self):
        return list(reference_module("andrews").ANGLE_NAMES)

    def errors(self, signals):
        andrews = reference_module("andrews")
        final = np.array([signals[name][-1] for name in andrews.ANGLE_NAMES])
        rel = np.abs(final - andrews.REFERENCE_ANGLES) / np.abs(andrews.REFERENCE_ANGLES)
        return {"error": float(np.max(rel))}


class Robertson(Problem):
    POINTS = 161

    def __init__(self):
        robertson = reference_module("robertson")
        super().__init__(
            key="robertson", title="Robertson's kinetics, index-1 DAE, t = 0 ... 1e11",
            dyadc_spec=str(MODELS / "Robertson.dyad"), stop=robertson.REFERENCE_T,
            grid=np.concatenate([[0.0], np.logspace(-5, np.log10(robertson.REFERENCE_T), self.POINTS - 1)]),
            scipy_module="scipy_robertson", scipy_options={"points": self.POINTS},
            error_label="max relative error of (y1, y2, y3) at t = 1e11",
            atol_ratio=1e-6,
            notes=["atol = 1e-6 * rtol for every contender: y2 is ~1e-13 at the end, so atol = rtol "
                   "would leave it unresolved.",
                   "dyadc integrates the DAE as written (the compiler solves the mass balance for y3); "
                   "scipy integrates the 2-state ODE with y3 eliminated by hand (analytic Jacobian).",
                   "Reference: the Test Set's solution at t = 1e11 (RADAU5, rtol = atol = 1e-15)."])

    def signal_names(self):
        return ["y1", "y2", "y3"]

    def errors(self, signals):
        robertson = reference_module("robertson")
        final = np.array([signals[name][-1] for name in ("y1", "y2", "y3")])
        return {"error": float(np.max(np.abs(final - robertson.REFERENCE_Y) / robertson.REFERENCE_Y))}


EXCAVATOR_GROUPS = {
    "positions": [f"{a}_joint.phi" for a in ("boom", "stick", "bucket")]
                 + [f"{link}.frame_b.{c}" for link in ("boom", "stick", "bucket") for c in ("x", "y")]
                 + [f"{a}_cyl.cylinder.s" for a in ("boom", "stick", "bucket")],
    "velocities": [f"{a}_joint.w" for a in ("boom", "stick", "bucket")]
                  + [f"{a}_cyl.cylinder.v" for a in ("boom", "stick", "bucket")],
    "pressures": [f"{a}_cyl.cylinder.p_{s}" for a in ("boom", "stick", "bucket") for s in ("a", "b")],
    "payload": ["soil.m_load"],
}


class Excavator(Problem):
    """Reference: the independent hand-derived model (tests/reference/excavator_minimal.py) at
    rtol = atol = 1e-12 with LSODA, restarted at the reference's waypoints."""
    REFERENCE_TOL = 1e-12

    def __init__(self, check_reference: bool = True):
        super().__init__(
            key="excavator", title="Excavator dig cycle (scene), t = 0 ... 12 s, 1201 points",
            dyadc_spec="MultibodyComponents.PlanarMechanics.examples.excavator.Excavator", stop=12.0,
            grid=np.linspace(0.0, 12.0, 1201), scipy_module="scipy_excavator", scipy_options={},
            error_label="max over signal groups of max over the grid of |y - y_ref| / max|y_ref| of the group")
        self.check_reference = check_reference
        self.reference_info: dict = {}

    def signal_names(self):
        return [name for group in EXCAVATOR_GROUPS.values() for name in group]

    def scipy_signals(self, output):
        return {name: output["signals"][name] for name in self.signal_names()}

    @cached_property
    def reference(self) -> dict[str, np.ndarray]:
        model = reference_module("excavator_minimal")
        began = time.perf_counter()
        out = model.simulate(self.grid, rtol=self.REFERENCE_TOL, atol=self.REFERENCE_TOL, method="LSODA",
                             split_at_waypoints=True)
        self.reference_info = {"method": "LSODA", "seconds": time.perf_counter() - began}
        if self.check_reference:
            began = time.perf_counter()
            other = model.simulate(self.grid, rtol=self.REFERENCE_TOL, atol=self.REFERENCE_TOL, method="Radau",
                                   split_at_waypoints=True)
            self.reference_info["check_seconds"] = time.perf_counter() - began
            self.reference_info["radau_vs_lsoda"] = self._group_errors(
                {n: other[n] for n in self.signal_names()}, out)
        return {n: np.asarray(out[n]) for n in self.signal_names()}

    def _group_errors(self, signals, reference) -> dict[str, float]:
        errors = {}
        for group, names in EXCAVATOR_GROUPS.items():
            scale = max(float(np.max(np.abs(reference[n]))) for n in names)
            errors[f"{group} max"] = max(float(np.max(np.abs(signals[n] - reference[n]))) for n in names) / scale
            errors[f"{group} final"] = max(abs(float(signals[n][-1] - reference[n][-1])) for n in names) / scale
        return errors

    def errors(self, signals):
        errors = self._group_errors(signals, self.reference)
        errors["error"] = max(errors[f"{g} max"] for g in EXCAVATOR_GROUPS)
        return errors


def all_problems(check_reference: bool = True) -> list[Problem]:
    return [Excavator(check_reference), Pendulum(), SwingingPendulum(), Andrews(), Robertson()]
