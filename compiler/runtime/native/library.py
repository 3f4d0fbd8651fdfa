"""The native IDAS driver library (dyad_idas.c, built by build.py) through ctypes: loading it once,
the C signatures, and one driver object per model library (`Driver`), with numpy arrays in and
out. Nothing here knows the run loop; integrator.py does."""
from __future__ import annotations

import ctypes
import sys
import threading
from pathlib import Path

import numpy as np

# in the Python environment (the project's .venv after `make install`), outside the package: it is
# built for this machine, never shipped in a wheel; a wheel user builds it with the command below
LIBRARY_PATH = Path(sys.prefix) / "lib" / "dyadc" / "libdyadidas.so"
BUILD_COMMAND = "python -m compiler.native.build"   # (make install runs it)

# IDAS's return flags (idas.h) by value, as IDAS names them
IDA_FLAGS = {-1: "IDA_TOO_MUCH_WORK", -2: "IDA_TOO_MUCH_ACC", -3: "IDA_ERR_FAIL", -4: "IDA_CONV_FAIL",
             -5: "IDA_LINIT_FAIL", -6: "IDA_LSETUP_FAIL", -7: "IDA_LSOLVE_FAIL", -8: "IDA_RES_FAIL",
             -9: "IDA_REP_RES_ERR", -10: "IDA_RTFUNC_FAIL", -11: "IDA_CONSTR_FAIL",
             -12: "IDA_FIRST_RES_FAIL", -13: "IDA_LINESEARCH_FAIL", -14: "IDA_NO_RECOVERY",
             -15: "IDA_NLS_INIT_FAIL", -16: "IDA_NLS_SETUP_FAIL", -17: "IDA_NLS_FAIL",
             -20: "IDA_MEM_NULL", -21: "IDA_MEM_FAIL", -22: "IDA_ILL_INPUT", -26: "IDA_BAD_T",
             -27: "IDA_BAD_DKY"}
# what dyad_ida_advance returns besides IDAS's negative flags
REACHED, ROOT, RUNAWAY, INTERRUPTED, PROPOSED = 0, 1, 2, 3, 4
COUNTER_NAMES = ("steps", "residual_evaluations", "jacobian_evaluations", "linear_solver_setups",
                 "error_test_failures", "newton_iterations", "newton_convergence_failures")

_DOUBLES = np.ctypeslib.ndpointer(dtype=np.float64, flags="C_CONTIGUOUS")
_INTS = np.ctypeslib.ndpointer(dtype=np.intc, flags="C_CONTIGUOUS")
_lock = threading.Lock()
_loaded: dict[str, object] = {}


def driver_library() -> tuple[ctypes.CDLL | None, str]:
    """The loaded driver library, or None and why it is not there (kept after the first call)."""
    with _lock:
        if "library" not in _loaded:
            _loaded["library"], _loaded["why"] = _load(LIBRARY_PATH)
        return _loaded["library"], _loaded["why"]


def _load(path: Path) -> tuple[ctypes.CDLL | None, str]:
    if not path.exists():
        return None, (f"the native IDAS driver is not built ({path} is missing; `make install` or "
                      f"`{BUILD_COMMAND}` builds it)")
    try:
        lib = ctypes.CDLL(str(path))
    except OSError as err:
        return None, f"the native IDAS driver at {path} does not load: {err}"
    vp, i, d, ci = ctypes.c_void_p, ctypes.c_int, ctypes.c_double, ctypes.c_char_p
    signatures = {
        "dyad_ida_new": (vp, [ci, i, i, i, i, ctypes.c_char_p, i]),
        "dyad_ida_free": (None, [vp]),
        "dyad_ida_message": (ci, [vp]),
        "dyad_ida_setup": (i, [vp, d, _DOUBLES, i, d, i, _INTS, _INTS, _INTS, d]),
        "dyad_ida_restart": (i, [vp, d, _DOUBLES, _DOUBLES, _DOUBLES, _INTS, d]),
        "dyad_ida_advance": (i, [vp, d, i, _DOUBLES, _DOUBLES, _DOUBLES, ctypes.POINTER(i), _DOUBLES,
                                 ctypes.c_long, ctypes.POINTER(d), _DOUBLES, _DOUBLES,
                                 ctypes.POINTER(i), ctypes.POINTER(i), i]),
        "dyad_ida_solve_algebraic": (i, [vp, d, _DOUBLES, _DOUBLES, _DOUBLES, i]),
        "dyad_ida_stats": (None, [vp, np.ctypeslib.ndpointer(dtype=np.int_, flags="C_CONTIGUOUS")]),
        "dyad_ida_sundials_version": (ci, []),
    }
    try:
        for name, (restype, argtypes) in signatures.items():
            function = getattr(lib, name)
            function.restype, function.argtypes = restype, argtypes
    except AttributeError as err:
        return None, f"the native IDAS driver at {path} is incomplete ({err}; `{BUILD_COMMAND}` rebuilds it)"
    return lib, ""


def sundials_version() -> str | None:
    lib, _ = driver_library()
    return None if lib is None else lib.dyad_ida_sundials_version().decode()


class Driver:
    """IDAS on one model library (its dyad_dae, jac_dyad_dae and, with watched rows, dyad_watch),
    set up once with its tolerances; `restart` puts it at a point, `advance` steps it on."""

    def __init__(self, library_path: str, nx: int, nz: int, np_: int, nrows: int):
        lib, why = driver_library()
        if lib is None:
            raise RuntimeError(why)
        self.lib, self.nx, self.nz, self.nrows = lib, nx, nz, nrows
        error = ctypes.create_string_buffer(1024)
        self.handle = lib.dyad_ida_new(str(library_path).encode(), nx, nz, np_, nrows, error, 1024)
        if not self.handle:
            raise RuntimeError(error.value.decode(errors="replace"))
        self._t, self._n = ctypes.c_double(), ctypes.c_int()
        self._row, self._direction = ctypes.c_int(), ctypes.c_int()

    def __del__(self):
        if getattr(self, "handle", None):
            self.lib.dyad_ida_free(self.handle)
            self.handle = None

    def message(self) -> str:
        return self.lib.dyad_ida_message(self.handle).decode(errors="replace")

    def setup(self, rtol: float, atol: np.ndarray, suppress_algebraic: bool, max_step: float,
              max_order: int, directions: np.ndarray, zero_sides: np.ndarray, proposes: np.ndarray,
              watch_atol: float) -> int:
        return self.lib.dyad_ida_setup(self.handle, rtol, np.ascontiguousarray(atol, dtype=float),
                                       int(suppress_algebraic), max_step, max_order,
                                       np.ascontiguousarray(directions, dtype=np.intc),
                                       np.ascontiguousarray(zero_sides, dtype=np.intc),
                                       np.ascontiguousarray(proposes, dtype=np.intc), watch_atol)

    def restart(self, t0: float, x0, z0, p, active: np.ndarray, step0: float) -> int:
        return self.lib.dyad_ida_restart(self.handle, t0, _vector(x0), _vector(z0), _vector(p),
                                         np.ascontiguousarray(active, dtype=np.intc), step0)

    def advance(self, reach: float, outputs, limit: np.ndarray, max_steps: int):
        """(flag, n outputs done, xs, zs, t, x, z, row, direction) of one dyad_ida_advance; in the
        main thread Ctrl-C stops it after the step it is in (INTERRUPTED)."""
        times = np.ascontiguousarray(outputs, dtype=float)
        n = len(times)
        xs, zs = np.empty((n, self.nx)), np.empty((n, self.nz))
        x, z = np.empty(self.nx), np.empty(self.nz)
        flag = self.lib.dyad_ida_advance(self.handle, reach, n, times, xs, zs, ctypes.byref(self._n),
                                         limit, max_steps, ctypes.byref(self._t), x, z,
                                         ctypes.byref(self._row), ctypes.byref(self._direction),
                                         int(threading.current_thread() is threading.main_thread()))
        k = self._n.value
        return flag, k, xs[:k].T, zs[:k].T, self._t.value, x, z, self._row.value, self._direction.value

    def solve_algebraic(self, t: float, x, z, p, max_steps: int) -> tuple[int, np.ndarray]:
        """(1 converged to round-off, 0 not, -1 no Newton step could be taken; z) solving the
        algebraic equations at (t, x) with parameters p from z, in C (IDAS is not touched)."""
        solved = np.array(z, dtype=float).reshape(-1)
        outcome = self.lib.dyad_ida_solve_algebraic(self.handle, t, _vector(x), solved, _vector(p), max_steps)
        return outcome, solved

    def counters(self) -> np.ndarray:
        out = np.zeros(len(COUNTER_NAMES), dtype=np.int_)
        self.lib.dyad_ida_stats(self.handle, out)
        return out


def _vector(values) -> np.ndarray:
    return np.ascontiguousarray(np.asarray(values, dtype=float).reshape(-1))
