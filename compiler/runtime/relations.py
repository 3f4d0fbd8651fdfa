"""Relations locked between events (Modelica's semantics; the compiler's side is
compiler/lower/relation_locks.py): every relation on unknowns in the integrated equations reads a
lock parameter, which the driver sets here at the start of each IDAS call, at the run's start and
after every event, and which holds while IDAS iterates. A condition therefore changes only where
its zero function is located crossing zero (watches.py, crossings.py), never between two Newton
iterations of one step.

Setting the locks is Modelica's event iteration: the relations are evaluated at the point, the
algebraic unknowns solved again with the new locks, and the relations evaluated again, until they
no longer change.
"""
from __future__ import annotations

import numpy as np

from .errors import InitializationFailed, SimulationFailed
from .initialization import restart_point
from .model import CompiledModel

LIVE = 2.0                   # a lock holding this evaluates its relation as written
MAX_EVENT_ITERATIONS = 20
METADATA_KEY = "relation_locks"
SLIDING_EVENTS = 20
SLIDING_WINDOW = 1e-9

_COMPARE = {">": np.greater, ">=": np.greater_equal, "<": np.less, "<=": np.less_equal}


def sliding(model: CompiledModel, events: list[dict]) -> SimulationFailed | None:
    """The failure to raise when the last SLIDING_EVENTS events are one relation flipping back and
    forth within SLIDING_WINDOW relative time: a sliding mode, which neither branch of the
    condition holds (`der(v) = ifelse(v > 0, -1, 1) + 0.5` at v = 0: each branch drives v across
    0, so with locked relations every flip is an event, 6e-12 s apart at t = 2, and the run would
    not get anywhere; with the relations live IDAS ground through 0.75 ms in 100,000 steps and
    failed)."""
    if len(events) < SLIDING_EVENTS:
        return None
    last = events[-SLIDING_EVENTS:]
    if len({e["event"] for e in last}) != 1:
        return None
    t, window = last[-1]["time"], last[-1]["time"] - last[0]["time"]
    if window > SLIDING_WINDOW * max(1.0, abs(t)):
        return None
    reason = (f"the condition {last[-1]['event']} switches back and forth ({SLIDING_EVENTS} times "
              f"within {window:.3g} s): a sliding mode, which neither branch of the condition holds; "
              f"the model needs an equation for its state on the switching surface (a stuck mode, "
              f"or hysteresis in the condition)")
    return SimulationFailed(f"simulation of {model.name} stopped at t = {t:.10g}: {reason}", t, reason)


def has_locks(model: CompiledModel) -> bool:
    return bool(model.metadata.get(METADATA_KEY))


def lock_indices(model: CompiledModel) -> np.ndarray:
    """The positions of the lock parameters in the parameter vector."""
    def build():
        names = {n: i for i, n in enumerate(model.parameter_names)}
        return np.array([names[lock["parameter"]] for lock in model.metadata.get(METADATA_KEY, ())],
                        dtype=int)
    return model.derived("relation_lock_indices", build)


def relation_values(model: CompiledModel, x, z, p, t: float) -> np.ndarray:
    """Each locked relation evaluated at (x, z, p, t) as 1.0 or 0.0 (its zero function is a row of
    the model's events function, which reads the other relations through their locks in p)."""
    locks = model.metadata.get(METADATA_KEY) or []
    if not locks:
        return np.zeros(0)
    zeros = np.asarray(model.events(x, z, p, t), dtype=float).reshape(-1)
    values = [_COMPARE[lock["operator"]](lock["sign"] * zeros[lock["row"]], 0.0) for lock in locks]
    return np.asarray(values, dtype=float)


def settle_relations(model: CompiledModel, p: np.ndarray, x, z, t: float,
                     live: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """(p with every lock set to its relation's value at this point, z solving the algebraic
    equations with those locks). Where the relations never settle (each setting makes another
    relation flip) or the algebraic equations have no solution with them, every lock is LIVE:
    the relations are evaluated as written, as without locks.

    `live`: every lock LIVE from this point, z as given. The driver asks for it when an IDAS call
    with locked relations failed: the locked branch may be undefined past its crossing (`if h > 0
    then -k * sqrt(h) else 0` integrated on below h = 0 has no value); with live relations the
    call crosses over and its crossing is located, after which the relations are locked again."""
    if not has_locks(model):
        return p, z
    index = lock_indices(model)
    p = np.array(p, dtype=float)
    z = np.asarray(z, dtype=float)
    if live:
        p[index] = LIVE
        return p, z
    start_z = z
    for _ in range(MAX_EVENT_ITERATIONS):
        values = relation_values(model, x, z, p, t)
        if np.array_equal(p[index], values):
            return p, z
        p[index] = values
        try:
            z = _solve_algebraics(model, p, t, x, z)
        except InitializationFailed:
            break
    p[index] = LIVE
    return p, _solve_algebraics(model, p, t, x, start_z)


def _solve_algebraics(model: CompiledModel, p, t, x, z) -> np.ndarray:
    if not model.algebraic_names:
        return z
    return restart_point(model, p, t, np.asarray(x, dtype=float), z).z
