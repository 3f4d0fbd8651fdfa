"""From the integrator's (x, z) at the output times to the user's signals: algebraic unknowns
polished onto their equations where a signal asked for depends on them, then the signals asked for.

Every evaluation here goes through `PointwiseEvaluator`: a function of (x, z, p, t) mapped over a
fixed block of points with the parameters shared by the block (not repeated per point), reading its
inputs from and writing its outputs to numpy memory (CasADi function buffers). Converting numpy to
CasADi matrices and back cost more than evaluating the excavator's 631 outputs (measured at 501
points: 21 ms through DM, 3.4 ms through buffers, bit-identical), and a map per number of points
was built again for every new segment length.

With `--codegen c` the model's library also holds the output function and the Newton step and
residual of the algebraic equations (compiler/lower/ccodegen.py); they are used where present:
the same expressions, the same numbers (bit-identical on the excavator), 3-5x less time.
"""
from __future__ import annotations

import threading
from typing import Sequence

import casadi as ca
import numpy as np

from .model import CompiledModel

BLOCK = 64            # points per mapped call
SMALL_BLOCK = 8       # points per call of the remainder; what remains of it goes point by point
# A subset of the outputs is evaluated on the VM when its SX instructions number less than
# 1/CHEAPER_IN_C of the full output function's, else by the full C function and then taken.
# Excavator, 1201 points (CPU ms): C, all 631 outputs (1869 instructions) 1.9-2.0; VM, 25 asked
# (227) 1.3, 5 (323) 1.3, 100 (1145) 4.1, 300 (1466) 5.1, all 6.5-7.4: even at 4 the VM wins.
CHEAPER_IN_C = 4.0


class PointwiseEvaluator:
    """`function(x, z, p, t)` at many points with one parameter vector: `evaluate(xs, zs, p, times)`
    returns one (rows x points) array per output of the function (dense, column-major rows for
    matrix outputs). Keeps nothing of a call but CasADi's call buffers (made once per thread and
    width, bound to the arrays anew at every call), so one evaluator serves any number of runs."""

    def __init__(self, function: ca.Function, block: int = BLOCK):
        if function.n_in() != 4:
            raise ValueError(f"{function.name()} takes {function.n_in()} inputs, not (x, z, p, t)")
        self.function = function
        self.block = block
        # (points per call, function): whole blocks first, then small blocks, then single points
        self.widths = [(width, function.map(f"{function.name()}_{width}", "serial", width, [2], []))
                       for width in sorted({block, SMALL_BLOCK}, reverse=True) if width > 1]
        self.widths.append((1, function))
        self.sizes_in = [function.nnz_in(i) for i in range(4)]
        self.stored_rows = [function.nnz_out(j) for j in range(function.n_out())]
        self._buffers = threading.local()
        self.dense_rows = [function.numel_out(j) for j in range(function.n_out())]
        # where each stored entry of an output goes in the dense column (None: already dense)
        self.scatter = [None if function.nnz_out(j) == function.numel_out(j)
                        else np.asarray(function.sparsity_out(j).find(), dtype=int)
                        for j in range(function.n_out())]

    def evaluate(self, xs: np.ndarray, zs: np.ndarray, p: np.ndarray, times,
                 into: np.ndarray | None = None) -> list[np.ndarray]:
        """`into`: a C-ordered (points x rows) array that receives the first output (dense
        outputs only); what is returned for it is then its transpose, a view."""
        times = np.ascontiguousarray(np.asarray(times, dtype=float).reshape(-1))
        n = len(times)
        # one point per row of a C-ordered array = CasADi's column-major layout of a mapped input
        columns = [np.ascontiguousarray(np.asarray(xs, dtype=float).reshape(self.sizes_in[0], n).T),
                   np.ascontiguousarray(np.asarray(zs, dtype=float).reshape(self.sizes_in[1], n).T)]
        shared = np.ascontiguousarray(np.asarray(p, dtype=float).reshape(-1))
        stored = [np.empty((n, rows)) for rows in self.stored_rows]
        if into is not None:
            if self.scatter[0] is not None or into.shape != stored[0].shape or not into.flags.c_contiguous:
                raise ValueError("`into` must be a C-ordered (points x rows) array of a dense output")
            stored[0] = into
        done = 0
        for width, function in self.widths:
            upto = done + (n - done) // width * width
            if upto > done:
                self._run(self._buffer(width, function), width, columns, shared, times, stored, done, upto)
            done = upto
        out = []
        for j, values in enumerate(stored):
            if self.scatter[j] is not None:
                dense = np.zeros((n, self.dense_rows[j]))
                dense[:, self.scatter[j]] = values
                values = dense
            out.append(values.T)
        return out

    def _buffer(self, width: int, function: ca.Function):
        """(buffer, call) of `function`, made once per thread (making one cost 14 us a call)."""
        made = self._buffers.__dict__.setdefault("by_width", {})
        if width not in made:
            made[width] = function.buffer()
        return made[width]

    @staticmethod
    def _run(buffer_call, width: int, columns, shared, times, stored, first: int, last: int):
        """Evaluate the function of `buffer_call` (one point, or a map of `width` points) over
        points first..last, reading and writing the rows of the arrays in place (each block's
        rows are contiguous). Every input and output is bound before each call."""
        buffer, call = buffer_call
        buffer.set_arg(2, memoryview(shared))
        for start in range(first, last, width):
            stop = start + width
            buffer.set_arg(0, memoryview(columns[0][start:stop]))
            buffer.set_arg(1, memoryview(columns[1][start:stop]))
            buffer.set_arg(3, memoryview(times[start:stop]))
            for j, array in enumerate(stored):
                buffer.set_res(j, memoryview(array[start:stop]))
            call()


def evaluator(model: CompiledModel, key, build) -> PointwiseEvaluator:
    """The evaluator of a function derived from `model` (built once per model and key)."""
    return model.derived(("evaluator",) + tuple(key), lambda: PointwiseEvaluator(build()))


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


def polish_algebraics(model: CompiledModel, xs: np.ndarray, zs: np.ndarray, p: np.ndarray,
                      grid: np.ndarray, iterations: int = 2) -> np.ndarray:
    """IDAS interpolates z between its steps, so at output times the algebraic equations hold only
    to the interpolation error. With the states fixed, a couple of Newton steps on 0 = alg(x, z)
    make the outputs satisfy them to round-off (the constraint of a mechanism to ~1e-15). A step
    is kept only where it does not increase the largest residual. `p` is one parameter vector or
    one column per point."""
    nz, n = zs.shape
    if nz == 0 or n == 0:
        return zs
    from .linear_solver import sparse_polish      # large sparse systems: sparse, point by point
    polished = sparse_polish(model, xs, zs, p, grid, iterations)
    if polished is not None:
        return polished
    z = np.array(zs, dtype=float)
    for first, last, p_run in _parameter_runs(p, n):
        z[:, first:last] = _polish_run(model, xs[:, first:last], z[:, first:last], p_run,
                                       np.asarray(grid, dtype=float)[first:last], iterations)
    return z


def _polish_run(model: CompiledModel, xs, z, p, times, iterations: int) -> np.ndarray:
    """The Newton steps on points that share p; r and its Jacobian are evaluated once per point
    and iterate (at an accepted candidate they are the candidate's), the last candidate's residual
    without the Jacobian, which no further step needs."""
    newton = evaluator(model, ("algebraic_newton",),
                       lambda: model.native_function("algebraic_newton") or model.algebraic_newton())
    residual = evaluator(model, ("algebraic_residual",),
                         lambda: model.native_function("algebraic_residual") or _residual_function(model))
    nz, n = z.shape
    r, jac = newton.evaluate(xs, z, p, times)
    for iteration in range(iterations):
        matrices = jac.T.reshape(n, nz, nz).transpose(0, 2, 1)       # column-major per point
        try:
            step = np.linalg.solve(matrices, r.T[:, :, None])[:, :, 0].T
        except np.linalg.LinAlgError:
            return z
        candidate = z - step
        last = iteration == iterations - 1
        if last:
            (r_new,) = residual.evaluate(xs, candidate, p, times)
        else:
            r_new, jac_new = newton.evaluate(xs, candidate, p, times)
        better = np.all(np.isfinite(r_new), axis=0) & (np.abs(r_new).max(axis=0) <= np.abs(r).max(axis=0))
        z[:, better] = candidate[:, better]
        if not last:
            r[:, better], jac[:, better] = r_new[:, better], jac_new[:, better]
    return z


def _residual_function(model: CompiledModel) -> ca.Function:
    """(x, z, p, t) -> alg, the same expressions as the first output of algebraic_newton."""
    x, z, p, t = model.symbols()
    return ca.Function("alg_residual", [x, z, p, t], [model.dae(x, z, p, t)[1]])


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
    runs = list(_parameter_runs(p, n))
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
    native = model.native_function("outputs")
    if native is not None and (key is None or _subset_cheaper_in_c(model, key)):
        return evaluator(model, ("outputs", "native"), lambda: native), (None if key is None else list(key))
    function, _ = output_rows_function(model, rows)
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
    if uses_z:
        zs = polish_algebraics(model, xs, zs, p, grid)
    return evaluate_outputs(model, xs, zs, p, grid, rows)


def _parameter_runs(p: np.ndarray, n: int):
    """(first, last, p) for each run of points sharing one parameter vector: `p` is one vector
    for all n points, or one column per point (a run's segments may differ in p)."""
    p = np.asarray(p, dtype=float)
    if p.ndim < 2:
        yield 0, n, p.reshape(-1)
        return
    if n == 0:
        return
    changes = np.nonzero(np.any(p[:, 1:] != p[:, :-1], axis=0))[0] + 1 if p.shape[0] else []
    bounds = [0, *[int(c) for c in changes], n]
    for first, last in zip(bounds[:-1], bounds[1:]):
        yield first, last, p[:, first]
