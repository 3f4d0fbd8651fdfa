"""Checks during the run: declared bounds (watched by IDAS as zero-crossing functions, so a run
stops where a bound is crossed, whatever the output grid), non-finite and runaway values."""
from __future__ import annotations


import casadi as ca
import numpy as np

from .errors import SimulationFailed
from .model import CompiledModel

RUNAWAY_LIMIT = 1e12     # |value| beyond this times max(1, nominal, |start|) means the run diverged


def bound_indicators(model: CompiledModel, outputs: ca.SX, atol: float = 0.0
                     ) -> tuple[ca.SX, list[tuple[str, str, float]]]:
    """value - min and max - value for every declared bound of an output, positive inside the
    domain and crossing zero where the run leaves it by more than round-off and the solver's own
    absolute tolerance (`atol`, scaled by the output's nominal value): a level that decays to its
    bound of zero is not a violation when the solver's error dips below it."""
    rows, labels = [], []
    for name, limits in sorted((model.metadata.get("bounds") or {}).items()):
        if name not in model._output_index:
            continue
        value = outputs[model._output_index[name]]
        for key in ("min", "max"):
            if key in limits:
                bound = float(limits[key])
                # ca.fmax: atol may be a symbol (the native driver's C watch takes it as input)
                slack = ca.fmax(_slack(bound), atol * abs(model.nominals.get(name, 1.0)))
                rows.append(value - (bound - slack) if key == "min" else bound + slack - value)
                labels.append((name, key, bound))
    return (ca.vertcat(*rows) if rows else ca.SX(0, 1)), labels


def _slack(bound: float) -> float:
    return 1e-12 + 1e-9 * abs(bound)


class BoundWarning(UserWarning):
    """A run left a declared min/max of a variable and went on (bounds="warn")."""


def bound_warning(model: CompiledModel, name: str, key: str, bound: float, value: float, t: float) -> str:
    return (f"{name} = {value:.6g} left its declared {key} = {bound:g} at t = {t:.10g} in {model.name}; "
            f"the run goes on (a bound is checked, not enforced: --strict-bounds, or bounds=\"error\", "
            f"stops the run there)")


def bound_violation(model: CompiledModel, name: str, key: str, bound: float, value: float,
                    t: float) -> SimulationFailed:
    reason = f"{name} = {value:.6g} is outside its declared {key} = {bound:g}"
    return SimulationFailed(f"simulation of {model.name} left the model's domain at t = {t:.10g}: "
                            f"{reason}", float(t), reason, variable=name)


def check_divergence(model: CompiledModel, grid: np.ndarray, xs: np.ndarray, scale: np.ndarray) -> None:
    """States that became non-finite or grew beyond RUNAWAY_LIMIT times their scale: the model
    diverges (a sign error, an unstable loop); stop at the first output time where it shows."""
    bad = ~np.isfinite(xs) | (np.abs(xs) > RUNAWAY_LIMIT * scale[:, None])
    if not bad.any():
        return
    k = int(np.argmax(bad.any(axis=0)))
    i = int(np.argmax(bad[:, k]))
    value = xs[i, k]
    name = model.state_names[i]
    if np.isfinite(value):
        reason = (f"{name} = {value:.6g} grew beyond {RUNAWAY_LIMIT:g} times its scale "
                  f"({scale[i]:g}): the model diverges")
    else:
        reason = f"{name} became {value}: the model diverges"
    raise SimulationFailed(f"simulation of {model.name} stopped at t = {grid[k]:.10g}: {reason}",
                           float(grid[k]), reason, variable=name)


def state_scales(model: CompiledModel, x0: np.ndarray) -> np.ndarray:
    nominal = np.array([abs(model.nominals.get(n, 1.0)) for n in model.state_names])
    return np.maximum.reduce([np.ones_like(nominal), nominal, np.abs(np.asarray(x0, dtype=float))])
