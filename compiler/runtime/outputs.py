"""From the integrator's (x, z) at the output times to the user's signals: algebraic unknowns
polished onto their equations where a signal asked for depends on them (polishing.py), then the
signals asked for, evaluated over all the points at once (pointwise.py).

Where the algebraic system is small, the first Newton step of the polishing and the outputs at
its result are one function (polishing.polished_outputs_function; excavator, all outputs: 2282 SX
instructions against 902 + 1869 apart). With `--codegen c` the model's library holds it, or, for
other models, the output function and the polishing's Newton function and residual
(compiler/lower/ccodegen.py); they are used where present: the same expressions, the same numbers
(bit-identical on the excavator), 3-5x less time.
"""
from __future__ import annotations

from typing import Sequence

import casadi as ca
import numpy as np

from .model import CompiledModel
# PointwiseEvaluator, BLOCK and polish_algebraics are imported from here by watches.py, crossings.py, ...
from .pointwise import BLOCK, PointwiseEvaluator, evaluator, parameter_runs  # noqa: F401
from . import polishing
from .polishing import polish_algebraics

# A subset of the outputs is evaluated on the VM when its SX instructions number less than
# 1/CHEAPER_IN_C of the full output function's, else by the full C function and then taken.
# Excavator, 1201 points (CPU ms): C, all 631 outputs (1869 instructions) 1.9-2.0; VM, 25 asked
# (227) 1.3, 5 (323) 1.3, 100 (1145) 4.1, 300 (1466) 5.1, all 6.5-7.4: even at 4 the VM wins.
CHEAPER_IN_C = 4.0


def output_rows_function(model: CompiledModel, rows: Sequence[int] | None) -> tuple[ca.Function, bool]:
    """The outputs `rows` (None: all) as one function of (x, z, p, t), and whether they depend
    on the algebraic unknowns z (if not, polishing z changes nothing they show)."""
    key = ("output_rows", None if rows is None else tuple(int(r) for r in rows))

    def build():
        x, z, p, t = model.symbols()
        values = model.outputs(x, z, p, t)
        if rows is not None:
            values = values[list(key[1])] if key[1] else ca.SX(0, 1)
        uses_z = bool(values.numel() and z.numel() and ca.depends_on(values, z))
        return ca.Function("outputs_asked", [x, z, p, t], [values]), uses_z
    return model.derived(key, build)


def evaluate_outputs(model: CompiledModel, xs: np.ndarray, zs: np.ndarray, p: np.ndarray,
                     grid: np.ndarray, rows: Sequence[int] | None = None) -> np.ndarray:
    """The outputs `rows` (default: every output) at every time of `grid`: a (rows x times)
    array; `p` is one parameter vector or one column per time."""
    n = len(grid)
    fast, taken = _outputs_evaluator(model, rows)
    count = fast.dense_rows[0] if taken is None else len(taken)
    if count == 0 or n == 0:
        return np.zeros((count, n))
    times = np.asarray(grid, dtype=float)
    runs = list(parameter_runs(p, n))
    if len(runs) == 1:
        values = fast.evaluate(xs, zs, runs[0][2], times)[0]
    else:
        rows_first = np.empty((n, fast.dense_rows[0]))      # each run fills its rows in place
        for first, last, p_run in runs:
            fast.evaluate(xs[:, first:last], zs[:, first:last], p_run, times[first:last],
                          into=rows_first[first:last])
        values = rows_first.T
    return values if taken is None else values[taken]


def _outputs_evaluator(model: CompiledModel, rows: Sequence[int] | None):
    """(evaluator, rows of its result to take, None: all): the model's C output function where it
    has one (for a subset too: CHEAPER_IN_C), else the VM function of just the rows asked for."""
    key = None if rows is None else tuple(int(r) for r in rows)
    function, uses_z = output_rows_function(model, rows)
    role = "outputs"
    if model.native_function(role) is None and not uses_z:
        role = "polished_outputs"           # a library of a small algebraic system: its outputs at
        # polished z are those at any z for rows that do not depend on z
    native = model.native_function(role)
    if native is not None and (key is None or _subset_cheaper_in_c(model, key)):
        return evaluator(model, (role, "native"), lambda: native), (None if key is None else list(key))
    return evaluator(model, ("outputs", key), lambda: function), None


def _subset_cheaper_in_c(model: CompiledModel, rows: tuple) -> bool:
    """Whether every output in C costs less than the rows asked for on the VM: compared by the
    count of their SX instructions, the VM's taking CHEAPER_IN_C times as long per instruction."""
    def decide():
        full = model.outputs
        subset, _ = output_rows_function(model, rows)
        if not (full.is_a("SXFunction") and subset.is_a("SXFunction")):
            return True
        return subset.n_instructions() * CHEAPER_IN_C >= full.n_instructions()
    return model.derived(("outputs in C", rows), decide)


def signals_at(model: CompiledModel, xs: np.ndarray, zs: np.ndarray, p: np.ndarray,
               grid: np.ndarray, rows: Sequence[int] | None = None) -> np.ndarray:
    """The outputs `rows` (default: all) at the points (xs, zs) of `grid`, z polished first when
    one of them depends on it: what a run reports."""
    if rows is not None and len(rows) == len(model.output_names) and \
            np.array_equal(rows, np.arange(len(rows))):
        rows = None                                 # every output, in order: the model's own function
    _, uses_z = output_rows_function(model, rows)
    if not uses_z:
        return evaluate_outputs(model, xs, zs, p, grid, rows)
    if len(model.algebraic_names) > polishing.FUSED_UP_TO:
        return evaluate_outputs(model, xs, polish_algebraics(model, xs, zs, p, grid), p, grid, rows)
    # the first Newton step and the outputs at its result in one pass; where a further step
    # moves z (rarely: polishing.SETTLED), the outputs there again
    fast, taken, fast_rows = _polished_outputs_evaluator(model, rows)
    n = len(grid)
    times = np.asarray(grid, dtype=float)
    step = polishing.newton_step(model)
    rows_first = np.empty((n, fast.dense_rows[0]))          # each run fills its rows in place
    dense = fast.scatter[0] is None
    for first, last, p_run in parameter_runs(p, n):
        x_run, z_run, t_run = xs[:, first:last], zs[:, first:last], times[first:last]
        values, z_next, kept, moves = fast.evaluate(x_run, z_run, p_run, t_run,
                                                    into=rows_first[first:last] if dense else None)
        polished = polishing.polish_run(step, x_run, np.array(z_run, dtype=float), p_run, t_run,
                                        first=(z_next, kept[0] > 0, moves))
        again = np.nonzero(np.any(polished != z_next, axis=0))[0]
        if again.size:
            values[:, again] = evaluate_outputs(model, x_run[:, again], polished[:, again], p_run,
                                                t_run[again], fast_rows)
        if not dense:
            rows_first[first:last] = values.T
    values = rows_first.T
    return values if taken is None else values[taken]


def _polished_outputs_evaluator(model: CompiledModel, rows: Sequence[int] | None):
    """(evaluator of polishing.polished_outputs_function, rows of its first output to take
    (None: all), the rows it evaluates (None: all)): the model's C function of every output where
    it has one (for a subset too: CHEAPER_IN_C), else the VM function of just the rows asked for."""
    key = None if rows is None else tuple(int(r) for r in rows)
    native = model.native_function("polished_outputs")
    if native is not None and (key is None or _polished_subset_cheaper_in_c(model, key)):
        return (evaluator(model, ("polished_outputs", "native"), lambda: native),
                None if key is None else list(key), None)
    return (evaluator(model, ("polished_outputs", key), lambda: polishing.polished_outputs_function(model, key)),
            None, key)


def _polished_subset_cheaper_in_c(model: CompiledModel, rows: tuple) -> bool:
    """_subset_cheaper_in_c for the outputs at polished z (the step counts on both sides)."""
    def decide():
        if not model.outputs.is_a("SXFunction"):
            return True
        full = polishing.polished_outputs_function(model, None)
        subset = polishing.polished_outputs_function(model, rows)
        return subset.n_instructions() * CHEAPER_IN_C >= full.n_instructions()
    return model.derived(("polished outputs in C", rows), decide)
