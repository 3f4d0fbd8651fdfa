"""A linear model written to a file (.json, .mat, .npz) and described as text for a terminal.

JSON keys: A, B, C, D (lists of rows), states, inputs, outputs (name lists), operating_point =
{"time": t, "states": {name: value}, "inputs": {name: value}, "parameters": {name: value}}; a
steady state adds "steady_residual". .mat and .npz hold the same (names as string arrays, the
operating point's values as vectors beside their names).
"""
from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from compiler.linear.system import LinearSystem

FORMATS = (".json", ".mat", ".npz")


def as_plain(system: LinearSystem) -> dict:
    data = {"A": system.A.tolist(), "B": system.B.tolist(), "C": system.C.tolist(),
            "D": system.D.tolist(), "states": list(system.states), "inputs": list(system.inputs),
            "outputs": list(system.outputs), "operating_point": system.operating_point()}
    if system.steady_residual is not None:
        data["steady_residual"] = system.steady_residual
    return data


def write(system: LinearSystem, path: str | os.PathLike) -> None:
    suffix = Path(path).suffix.lower()
    if suffix not in FORMATS:
        raise ValueError(f"unknown linear-model format {suffix!r} (use one of {', '.join(FORMATS)})")
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    if suffix == ".json":
        Path(path).write_text(json.dumps(as_plain(system), indent=1) + "\n", encoding="utf-8")
        return
    point = system.operating_point()
    arrays = {"A": system.A, "B": system.B, "C": system.C, "D": system.D,
              "states": np.array(system.states, dtype=str), "inputs": np.array(system.inputs, dtype=str),
              "outputs": np.array(system.outputs, dtype=str), "time": np.array(system.time)}
    for group in ("states", "inputs", "parameters"):
        arrays[f"operating_point_{group}_names"] = np.array(list(point[group]), dtype=str)
        arrays[f"operating_point_{group}"] = np.array(list(point[group].values()), dtype=float)
    if suffix == ".npz":
        np.savez(path, **arrays)
    else:
        import scipy.io          # names as cell arrays of strings (char matrices would pad them)
        scipy.io.savemat(path, {k: (np.array(list(v), dtype=object) if v.dtype.kind == "U" else v)
                                for k, v in arrays.items()})


def summary(system: LinearSystem, max_transfer_states: int = 6, max_channels: int = 4) -> str:
    """Poles, DC gain and, for a small system, its transfer functions, as lines of text."""
    lines = [f"linear model at t = {system.time:g}: {len(system.states)} states, "
             f"{len(system.inputs)} inputs, {len(system.outputs)} outputs"
             + (" (minimal realization)" if system.minimal else "")]
    if system.steady_residual is not None:
        lines.append(f"steady state: largest residual of der(x) = 0, alg = 0 is {system.steady_residual:.3g}")
    if len(system.states) <= 12:
        lines.append("states: " + ", ".join(system.states))
    poles = sorted(system.poles(), key=lambda p: (p.real, p.imag))
    lines.append("poles:" + ("" if poles else " none"))
    lines += [f"  {complex_text(p)}" for p in poles[:40]]
    if len(poles) > 40:
        lines.append(f"  ... and {len(poles) - 40} more")
    if system.inputs and system.outputs:
        gain = system.dc_gain()
        lines.append("DC gain (rows: outputs, columns: inputs " + ", ".join(system.inputs) + "):")
        lines += [f"  {name}: " + "  ".join(f"{v:.6g}" for v in row) for name, row in zip(system.outputs, gain)]
        small = len(system.states) <= max_transfer_states and \
            len(system.inputs) * len(system.outputs) <= max_channels
        if small:
            lines += transfer_functions(system)
    return "\n".join(lines)


def transfer_functions(system: LinearSystem) -> list[str]:
    import control
    tf = control.ss2tf(control.ss(system.A, system.B, system.C, system.D)) if system.A.size else None
    lines = []
    for i, output in enumerate(system.outputs):
        for j, input_ in enumerate(system.inputs):
            if tf is None:
                text = f"{system.D[i, j]:.6g}"
            else:
                num, den = _trimmed(np.atleast_1d(tf.num[i][j])), np.atleast_1d(tf.den[i][j])
                text = f"({_polynomial(num)}) / ({_polynomial(den)})"
            lines.append(f"{output} / {input_} = {text}")
    return lines


def _trimmed(coefficients: np.ndarray) -> np.ndarray:
    scale = np.abs(coefficients).max(initial=0.0)
    keep = np.nonzero(np.abs(coefficients) > 1e-12 * max(scale, 1e-300))[0]
    return coefficients[keep[0]:] if len(keep) else np.zeros(1)


def _polynomial(coefficients: np.ndarray) -> str:
    degree = len(coefficients) - 1
    terms = []
    for k, c in enumerate(coefficients):
        power = degree - k
        if c == 0:
            continue
        factor = {0: "", 1: " s"}.get(power, f" s^{power}")
        terms.append(f"{c:.6g}{factor}")
    return " + ".join(terms).replace("+ -", "- ") or "0"


def complex_text(p: complex) -> str:
    """A pole as text: its real part alone when it is real (to 1e-12 of its size)."""
    if abs(p.imag) <= 1e-12 * max(abs(p), 1.0):
        return f"{p.real:.6g}"
    return f"{p.real:.6g} {'+' if p.imag > 0 else '-'} {abs(p.imag):.6g}i"
