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
from pathlib import Path
from typing import Any, Mapping

import numpy as np

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


def frequencies(settings: Mapping[str, Any], systems) -> np.ndarray | None:
    """The grid wl..wu (rad/s, num_frequencies points); -1 bounds from the poles of `systems`."""
    wl, wu = float(settings.get("wl", -1)), float(settings.get("wu", -1))
    if wl > 0 and wu > wl:
        return np.logspace(math.log10(wl), math.log10(wu), int(settings.get("num_frequencies", 3000)))
    magnitudes = [abs(p) for s in systems for p in np.linalg.eigvals(s.A) if abs(p) > 1e-9] if systems else []
    low = wl if wl > 0 else (min(magnitudes) / 100 if magnitudes else 1e-2)
    high = wu if wu > low else (max(magnitudes) * 100 if magnitudes else 1e3)
    return np.logspace(math.log10(low), math.log10(high), int(settings.get("num_frequencies", 1000)))


def linear_analysis(flat, settings: Mapping[str, Any], prefix: str, params=None) -> AnalysisReport:
    import control
    request = Request(inputs=names(settings["inputs"]), outputs=names(settings["outputs"]),
                      opened=names(settings["loop_openings"]), params=dict(params or {}))
    system = linearize_spec(flat, request, cache=False)
    report = AnalysisReport(systems={"linear": system})
    sys_ = system.to_control()
    omega = frequencies(settings, [system])
    report.files.append(_bode([(sys_, "")], omega, f"{prefix}_bode.png", "Bode plot"))
    duration = float(settings.get("duration", -1))
    step = control.step_response(sys_, T=duration if duration > 0 else None)
    report.files.append(_step(step, system, f"{prefix}_step.png"))
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
        report.files.append(_nyquist(loop, omega, f"{prefix}_nyquist.png"))
    report.files.append(_bode([(loop, "L = PC")], omega, f"{prefix}_bode.png", "loop transfer"))
    report.files.append(_bode(list((g, name) for name, g in gang.items()), omega,
                              f"{prefix}_gangoffour.png", "gang of four", magnitude_only=True))
    closed = control.feedback(loop, np.eye(loop.noutputs))
    report.lines += [f"closed-loop poles: " + ", ".join(_complex(x) for x in sorted(
        closed.poles(), key=lambda z: (z.real, z.imag)))]
    duration = float(settings.get("duration", -1))
    report.files.append(_steps({"reference -> measurement (T)": gang["T"],
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
    report.files.append(_bode(curves, omega, f"{prefix}_sensitivity.png", "sensitivity", magnitude_only=True))
    return report


RUNNERS = {"LinearAnalysis": linear_analysis, "ClosedLoopAnalysis": closed_loop_analysis,
           "ClosedLoopSensitivityAnalysis": sensitivity_analysis}


# -- numbers and plots ------------------------------------------------------------------------------

def _peak(system, omega: np.ndarray) -> float:
    response = system(1j * omega)
    magnitude = np.abs(np.asarray(response)).reshape(-1, len(omega)) if np.ndim(response) else np.abs(response)
    return float(np.max(magnitude))


def _damping(system: LinearSystem) -> list[str]:
    lines = ["pole                       damping   frequency (rad/s)   time constant (s)"]
    for p in sorted(system.poles(), key=lambda z: (abs(z), z.imag)):
        w = abs(p)
        zeta = -p.real / w if w > 0 else 1.0
        tau = -1 / p.real if p.real < 0 else math.inf
        lines.append(f"{_complex(p):<26} {zeta:8.4g}   {w:17.6g}   {tau:17.6g}")
    return lines


def _complex(p: complex) -> str:
    if abs(p.imag) <= 1e-12 * max(abs(p), 1.0):
        return f"{p.real:.6g}"
    return f"{p.real:.6g} {'+' if p.imag > 0 else '-'} {abs(p.imag):.6g}i"


def _db(gain: float) -> str:
    return "infinite" if not np.isfinite(gain) else f"{20 * math.log10(gain):.4g} dB ({gain:.4g})"


def _figure(rows: int = 1):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt, plt.subplots(rows, 1, figsize=(7, 2.6 * rows + 0.6), squeeze=False)


def _bode(curves, omega, path: str, title: str, magnitude_only: bool = False) -> str:
    plt, (fig, axes) = _figure(1 if magnitude_only else 2)
    for system, label in curves:
        response = np.asarray(system(1j * omega)).reshape(-1, len(omega))
        for k, row in enumerate(response):
            name = label if response.shape[0] == 1 else f"{label} [{k + 1}]"
            axes[0][0].loglog(omega, np.abs(row), label=name or None)
            if not magnitude_only:
                axes[1][0].semilogx(omega, np.degrees(np.unwrap(np.angle(row))), label=name or None)
    axes[0][0].set_ylabel("magnitude")
    axes[0][0].set_title(title)
    if not magnitude_only:
        axes[1][0].set_ylabel("phase (deg)")
    axes[-1][0].set_xlabel("frequency (rad/s)")
    for row in axes:
        row[0].grid(True, which="both", alpha=0.3)
        if any(label for _, label in curves):
            row[0].legend(fontsize=8)
    return _save(plt, fig, path)


def _nyquist(loop, omega, path: str) -> str:
    plt, (fig, axes) = _figure(1)
    response = np.asarray(loop(1j * omega)).reshape(-1)
    ax = axes[0][0]
    ax.plot(response.real, response.imag, label="L(iw)")
    ax.plot(response.real, -response.imag, "--", alpha=0.5, label="L(-iw)")
    ax.plot([-1], [0], "r+", markersize=12, label="-1")
    ax.set_xlabel("real")
    ax.set_ylabel("imaginary")
    ax.set_title("Nyquist plot of the loop transfer")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return _save(plt, fig, path)


def _step(step, system: LinearSystem, path: str) -> str:
    plt, (fig, axes) = _figure(1)
    outputs = np.asarray(step.outputs).reshape(len(system.outputs), len(system.inputs), -1)
    for i, out in enumerate(system.outputs):
        for j, inp in enumerate(system.inputs):
            axes[0][0].plot(step.time, outputs[i, j], label=f"{inp} -> {out}")
    axes[0][0].set_xlabel("time (s)")
    axes[0][0].set_title("step response of the linear model")
    axes[0][0].grid(True, alpha=0.3)
    axes[0][0].legend(fontsize=8)
    return _save(plt, fig, path)


def _steps(systems: Mapping[str, Any], duration: float, path: str) -> str:
    import control
    plt, (fig, axes) = _figure(1)
    for label, system in systems.items():
        step = control.step_response(system, T=duration if duration > 0 else None)
        axes[0][0].plot(step.time, np.asarray(step.outputs).reshape(-1, len(step.time))[0], label=label)
    axes[0][0].set_xlabel("time (s)")
    axes[0][0].set_title("closed-loop step responses")
    axes[0][0].grid(True, alpha=0.3)
    axes[0][0].legend(fontsize=8)
    return _save(plt, fig, path)


def _save(plt, fig, path: str) -> str:
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
