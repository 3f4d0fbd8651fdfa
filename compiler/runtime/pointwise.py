"""Evaluating a function of (x, z, p, t) at many points at once: `PointwiseEvaluator` maps it over
a fixed block of points with the parameters shared by the block (not repeated per point), reading
its inputs from and writing its outputs to numpy memory (CasADi function buffers). Converting numpy
to CasADi matrices and back cost more than evaluating the excavator's 631 outputs (measured at 501
points: 21 ms through DM, 3.4 ms through buffers, bit-identical), and a map per number of points
was built again for every new segment length. Used for the outputs (outputs.py), the polishing
of z (polishing.py) and the watched functions (watches.py).
"""
from __future__ import annotations

import threading

import casadi as ca
import numpy as np

from .model import CompiledModel

BLOCK = 64            # points per mapped call
SMALL_BLOCK = 8       # points per call of the remainder; what remains of it goes point by point


class PointwiseEvaluator:
    """`function(x, z, p, t)` at many points with one parameter vector: `evaluate(xs, zs, p, times)`
    returns one (rows x points) array per output of the function (dense, column-major rows for
    matrix outputs). Keeps nothing of a call but CasADi's call buffers (made once per thread and
    width, bound to the arrays anew at every call), so one evaluator serves any number of runs."""

    def __init__(self, function: ca.Function, block: int = BLOCK):
        """`block`: the points per mapped call (1: no map, for a function evaluated at single
        points only)."""
        if function.n_in() != 4:
            raise ValueError(f"{function.name()} takes {function.n_in()} inputs, not (x, z, p, t)")
        self.function = function
        self.block = block
        # (points per call, function): whole blocks first, then small blocks, then single points
        self.widths = [(width, function.map(f"{function.name()}_{width}", "serial", width, [2], []))
                       for width in sorted({block, min(block, SMALL_BLOCK)}, reverse=True) if width > 1]
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


def parameter_runs(p: np.ndarray, n: int):
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
