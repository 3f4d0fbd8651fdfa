"""Dyad's linear analyses on a flat model, with python-control for frequency responses, margins
and time responses:

- LinearAnalysis: the linear model from `inputs` to `outputs` (loops opened at `loop_openings`):
  a Bode plot and a step response over `duration`, poles with damping;
- ClosedLoopAnalysis: the plant P (control_input -> measurement, loop opened at the control
  input) and the controller C (measurement -> control input, opened at the measurement, negated
  when `pos_feedback`): L = P C, the Bode and Nyquist plots of L with its gain and phase margins,
  the gang of four S, T, PS, CS, step responses from reference (T) and input disturbance (PS);
- ClosedLoopSensitivityAnalysis: S at each analysis point, its peak Ms and the margins it
  guarantees (gain margin >= Ms/(Ms-1), phase margin >= 2 asin(1/(2 Ms))).

Each returns an AnalysisReport: text lines for the terminal, the numbers, and the files written.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from compiler.linear.files import complex_text
from compiler.linear.plots import bode_plot, frequency_grid, nyquist_plot, step_plot, steps_plot
from compiler.linear.request import Request, closed_loop_function, linearize_spec
from compiler.linear.system import LinearSystem


@dataclass
class AnalysisReport:
    lines: list[str] = field(default_factory=list)
    numbers: dict[str, Any] = field(default_factory=dict)
    files: list[str] = field(default_factory=list)
    systems: dict[str, LinearSystem] = field(default_factory=dict)


def names(value) -> tuple[str, ...]:
    return (value,) if isinstance(value, str) else tuple(value)


def frequencies(settings: Mapping[str, Any], systems) -> np.ndarray:
    """The grid wl..wu (rad/s, num_frequencies points); -1 bounds from the poles of `systems`."""
    return frequency_grid(systems, float(settings.get("wl", -1)), float(settings.get("wu", -1)),
                          int(settings.get("num_frequencies", 1000)))


def linear_analysis(flat, settings: Mapping[str, Any], prefix: str, params=None) -> AnalysisReport:
    import control
    request = Request(inputs=names(settings["inputs"]), outputs=names(settings["outputs"]),
                      opened=names(settings["loop_openings"]), params=dict(params or {}))
    system = linearize_spec(flat, request, cache=False)
    report = AnalysisReport(systems={"linear": system})
    sys_ = system.to_control()
    omega = frequencies(settings, [system])
    report.files.append(bode_plot([(sys_, "")], omega, f"{prefix}_bode.png", "Bode plot"))
    duration = float(settings.get("duration", -1))
    step = control.step_response(sys_, T=duration if duration > 0 else None)
    report.files.append(step_plot(step, system, f"{prefix}_step.png"))
    report.lines += _damping(system)
    report.numbers["poles"] = [complex(p) for p in system.poles()]
    return report


def closed_loop_analysis(flat, settings: Mapping[str, Any], prefix: str, params=None) -> AnalysisReport:
    import control
    measurement, control_input = names(settings["measurement"]), names(settings["control_input"])
    openings = names(settings["loop_openings"])
    plant = linearize_spec(flat, Request(inputs=control_input, outputs=measurement, params=dict(params or {}),
                                         opened=openings + control_input), cache=False)
    controller = linearize_spec(flat, Request(inputs=measurement, outputs=control_input, params=dict(params or {}),
                                              opened=openings + measurement), cache=False)
    p = plant.minimal_realization().to_control()
    c = controller.minimal_realization().to_control()
    if settings.get("pos_feedback", True):
        c = -c
    loop = p * c
    gang = {"S": control.feedback(control.ss([], [], [], np.eye(loop.noutputs)), loop),
            "T": control.feedback(loop, np.eye(loop.noutputs)), "PS": control.feedback(p, c),
            "CS": control.feedback(c, p)}
    omega = frequencies(settings, [plant, controller])
    report = AnalysisReport(systems={"plant": plant, "controller": controller})
    if loop.ninputs == 1 and loop.noutputs == 1:
        gm, pm, _, wcg, wcp, _ = control.stability_margins(loop, epsw=float(omega[0]))   # in the band
        report.numbers.update(gain_margin=float(gm), phase_margin_deg=float(pm),
                              phase_crossover=float(wcg), gain_crossover=float(wcp))
        gain_text = _db(gm) + (f" at {wcg:.4g} rad/s" if np.isfinite(gm) else "")
        report.lines.append(f"loop transfer L = P C at {', '.join(control_input)}: gain margin "
                            f"{gain_text}, phase margin {pm:.4g} deg at {wcp:.4g} rad/s")
        disk, disk_gain_db, disk_phase = control.disk_margins(loop, omega)   # balanced (skew 0)
        report.numbers.update(disk_margin=float(disk), disk_gain_margin_db=float(disk_gain_db),
                              disk_phase_margin_deg=float(disk_phase))
        report.lines.append(f"disk margin {disk:.4g}: gain margin {disk_gain_db:.4g} dB and phase "
                            f"margin {disk_phase:.4g} deg together (over {omega[0]:.3g}..{omega[-1]:.3g} rad/s)")
        report.files.append(nyquist_plot(loop, omega, f"{prefix}_nyquist.png"))
    report.files.append(bode_plot([(loop, "L = PC")], omega, f"{prefix}_bode.png", "loop transfer"))
    report.files.append(bode_plot(list((g, name) for name, g in gang.items()), omega,
                              f"{prefix}_gangoffour.png", "gang of four", magnitude_only=True))
    closed = control.feedback(loop, np.eye(loop.noutputs))
    report.lines += [f"closed-loop poles: " + ", ".join(complex_text(x) for x in sorted(
        closed.poles(), key=lambda z: (z.real, z.imag)))]
    duration = float(settings.get("duration", -1))
    report.files.append(steps_plot({"reference -> measurement (T)": gang["T"],
                                "input disturbance -> measurement (PS)": gang["PS"]},
                               duration, f"{prefix}_step.png"))
    peak = _peak(gang["S"], omega)
    report.numbers["Ms"] = peak
    report.lines.append(f"sensitivity peak Ms = {peak:.4g}")
    return report


def sensitivity_analysis(flat, settings: Mapping[str, Any], prefix: str, params=None) -> AnalysisReport:
    request = Request(opened=names(settings["loop_openings"]), params=dict(params or {}))
    report = AnalysisReport()
    curves = []
    found = {}
    for point in names(settings["analysis_points"]):
        s = closed_loop_function(flat, "sensitivity", point, request)
        report.systems[point] = s
        found[point] = s.to_control()
    omega = frequencies(settings, list(report.systems.values()))
    for point, s in found.items():
        peak = _peak(s, omega)
        report.numbers[point] = {"Ms": peak, "gain_margin_at_least": peak / (peak - 1) if peak > 1 else math.inf,
                                 "phase_margin_at_least_deg": math.degrees(2 * math.asin(min(1.0, 1 / (2 * peak))))}
        bound = report.numbers[point]
        report.lines.append(f"S at {point}: peak Ms = {peak:.4g} (gain margin >= "
                            f"{bound['gain_margin_at_least']:.4g}, phase margin >= "
                            f"{bound['phase_margin_at_least_deg']:.4g} deg)")
        curves.append((s, f"S at {point} (Ms = {peak:.3g})"))
    report.files.append(bode_plot(curves, omega, f"{prefix}_sensitivity.png", "sensitivity", magnitude_only=True))
    return report


RUNNERS = {"LinearAnalysis": linear_analysis, "ClosedLoopAnalysis": closed_loop_analysis,
           "ClosedLoopSensitivityAnalysis": sensitivity_analysis}


# -- numbers ----------------------------------------------------------------------------------------

def _peak(system, omega: np.ndarray) -> float:
    """The largest |entry| of the frequency response over the band of `omega`: the grid's
    largest, refined by golden-section search in log frequency between its neighbours."""
    def largest(w: float) -> float:
        return float(np.max(np.abs(np.asarray(system(1j * w)))))

    values = [largest(w) for w in omega]
    k = int(np.argmax(values))
    low, high = math.log(omega[max(k - 1, 0)]), math.log(omega[min(k + 1, len(omega) - 1)])
    ratio = (math.sqrt(5) - 1) / 2
    for _ in range(80):
        a, b = high - ratio * (high - low), low + ratio * (high - low)
        if largest(math.exp(a)) >= largest(math.exp(b)):
            high = b
        else:
            low = a
    return max(values[k], largest(math.exp((low + high) / 2)))


def _damping(system: LinearSystem) -> list[str]:
    lines = ["pole                       damping   frequency (rad/s)   time constant (s)"]
    for p in sorted(system.poles(), key=lambda z: (abs(z), z.imag)):
        w = abs(p)
        zeta = -p.real / w if w > 0 else 1.0
        tau = -1 / p.real if p.real < 0 else math.inf
        lines.append(f"{complex_text(p):<26} {zeta:8.4g}   {w:17.6g}   {tau:17.6g}")
    return lines


def _db(gain: float) -> str:
    return "infinite" if not np.isfinite(gain) else f"{20 * math.log10(gain):.4g} dB ({gain:.4g})"
