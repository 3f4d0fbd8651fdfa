"""SUNDIALS IDAS through CasADi: the solver's messages and options. Kept apart from the integrator
so that its flags, explanations and tolerance rules are read in one place."""
from __future__ import annotations

import atexit
import io
import os
import re
import sys
import tempfile
import threading
from typing import Mapping

from .errors import ModelInputError, did_you_mean
from .model import CompiledModel

# Readable explanations of the IDAS return flags that CasADi reports.
IDAS_REASONS = {
    "IDA_TOO_MUCH_WORK": "too many steps (max_steps) before reaching the next output time",
    "IDA_TOO_MUCH_ACC": "the requested accuracy is below machine precision",
    "IDA_ERR_FAIL": "error test failed repeatedly or with |h| = hmin (step size collapsed)",
    "IDA_CONV_FAIL": "corrector (Newton) convergence failed repeatedly or with |h| = hmin "
                     "(the algebraic equations may have no solution here, or the model is singular)",
    "IDA_LINIT_FAIL": "linear solver initialisation failed",
    "IDA_LSETUP_FAIL": "linear solver setup failed (singular iteration matrix?)",
    "IDA_LSOLVE_FAIL": "linear solve failed (singular iteration matrix?)",
    "IDA_RES_FAIL": "the residual function failed (NaN or Inf in the equations?)",
    "IDA_REP_RES_ERR": "the residual function failed repeatedly (NaN or Inf in the equations?)",
    "IDA_RTFUNC_FAIL": "the root function failed",
    "IDA_CONSTR_FAIL": "inequality constraints could not be met",
    "IDA_FIRST_RES_FAIL": "the residual function failed at the first call",
    "IDA_LINESEARCH_FAIL": "line search failed",
    "IDA_NO_RECOVERY": "the residual function failed recoverably but the corrector could not recover",
    "IDA_ILL_INPUT": "illegal input to IDAS",
    "IDA_MEM_NULL": "IDAS memory missing",
}


def idas_reason(text: str, solver_messages: str = "") -> str:
    """IDAS's flag from CasADi's exception text, explained, plus SUNDIALS's own last message."""
    match = re.search(r'returned "?(IDA_[A-Z_]+)"?', text)
    if match:
        flag = match.group(1)
        reason = f"{flag}: {IDAS_REASONS.get(flag, 'see the IDAS documentation')}"
    else:
        last = [line.strip() for line in text.strip().splitlines() if line.strip()]
        reason = last[-1] if last else "unknown solver error"
    # SUNDIALS prefixes "At t = ..." in its own (possibly rescaled) time; we report time ourselves.
    said = [re.sub(r"^At t = [^,]*,[ ,]*", "", line.strip()) for line in solver_messages.splitlines()
            if line.strip()]
    return f"{reason} (IDAS: {said[-1]})" if said and said[-1] else reason


def failure_time(solver_messages: str) -> float | None:
    """The time SUNDIALS says it failed at ("At t = 0.5, mxstep steps taken ..."), in the
    solver's own time; None when it said none. CasADi's `tcur` after a failure is the last output
    time reached, which can be far before the failure (t = 0 on a coarse output grid)."""
    said = re.findall(r"At t = ([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)", solver_messages)
    return float(said[-1]) if said else None


class CapturedStderr:
    """Collect what C code (SUNDIALS) writes to file descriptor 2 during a solver call, so that its
    message becomes part of our error instead of stray text. A no-op where fd 2 is unusable."""

    def __init__(self):
        self.text = ""
        self._saved: int | None = None
        self._file = None
        self._python = None

    def __enter__(self) -> "CapturedStderr":
        # CasADi prints SUNDIALS's messages through Python's sys.stderr, which may not be fd 2
        # (a caller that redirected it): take those too
        self._python, sys.stderr = sys.stderr, io.StringIO()
        try:
            self._python.flush()
            self._file = _scratch_file()
            self._saved = os.dup(2)
            os.dup2(self._file.fileno(), 2)
        except (OSError, ValueError, AttributeError):
            self._restore()
        return self

    def __exit__(self, *exc) -> None:
        self._restore()

    def _restore(self) -> None:
        if self._python is not None:
            self.text += sys.stderr.getvalue()
            sys.stderr, self._python = self._python, None
        if self._saved is not None:
            os.dup2(self._saved, 2)
            os.close(self._saved)
            self._saved = None
        if self._file is not None:
            self._file.seek(0)
            self.text += self._file.read().decode("utf-8", "replace")
            if self._file is getattr(_scratch, "file", None):
                self._file.seek(0)
                self._file.truncate()
                _scratch.busy = False
            else:
                self._file.close()
            self._file = None


_scratch = threading.local()


def _scratch_file():
    """One temporary file per thread for CapturedStderr, emptied after each use: creating one per
    IDAS call cost 50 us (a switching run makes dozens of calls). A capture inside a capture gets
    a file of its own."""
    file = getattr(_scratch, "file", None)
    if file is None or file.closed:
        file = _scratch.file = tempfile.TemporaryFile(mode="w+b")
        atexit.register(file.close)          # else a ResourceWarning at the interpreter's exit
    elif file.tell() or getattr(_scratch, "busy", False):
        return tempfile.TemporaryFile(mode="w+b")
    _scratch.busy = True
    return file


def integrator_options(model: CompiledModel, rtol: float, atol, max_steps: int,
                        extra: Mapping | None, switched: bool = False) -> dict:
    # calc_ic: CasADi starts IDAS with der(x) = 0 unless told otherwise (measured: the error test
    # then collapses h at t0 on an RC step), and init_xdot cannot change between chunks, so IDAS
    # itself completes der(x) (and re-polishes z) from our consistent point at every (re)start.
    # suppress_algebraic: the algebraic unknowns (accelerations, forces) of an index-1 DAE are
    # functions of the states; leaving them in the error test makes IDAS chase their kinks
    # (measured on the excavator at rtol 1e-6: 27150 steps with, 1040 without, same accuracy).
    opts = {"reltol": float(rtol), "max_num_steps": int(max_steps), "calc_ic": True,
            "suppress_algebraic": True,
            "disable_internal_warnings": True, "show_eval_warnings": False}
    names = model.state_names + model.algebraic_names
    controlled = error_controlled(model, switched)
    if controlled:
        opts["suppress_algebraic"] = False
    if isinstance(atol, Mapping) or model.nominals or controlled:
        base = float(atol.get("*", 1e-6)) if isinstance(atol, Mapping) else float(atol)
        per = {n: base * abs(model.nominals.get(n, 1.0)) for n in names}
        if isinstance(atol, Mapping):
            for name, value in atol.items():
                if name == "*":
                    continue
                if name not in per:
                    raise ModelInputError(f"atol given for '{name}', which is not a state or "
                                          f"algebraic unknown of {model.name}"
                                          + did_you_mean(name, names))
                per[name] = float(value)
        # the other algebraic unknowns stay out of the error test, as with suppress_algebraic
        # (unless the caller gave them a tolerance of their own)
        if controlled:
            given = set(atol) if isinstance(atol, Mapping) else set()
            free = set(model.algebraic_names) - controlled - given
            floor = max(base, DUMMY_ATOL_FLOOR)
            for name in controlled - given:
                per[name] = floor * abs(model.nominals.get(name, 1.0))
            opts["abstolv"] = [UNCONTROLLED if n in free else per[n] for n in names]
        else:
            opts["abstolv"] = [per[n] for n in names]
        opts["abstol"] = base
    else:
        opts["abstol"] = float(atol)
    from .linear_solver import linear_solver_options      # CSparse's LU on large dense models
    opts.update(linear_solver_options(len(names), model))
    opts.update(extra or {})
    return opts


UNCONTROLLED = 1e300     # an absolute tolerance that takes an unknown out of IDAS's error test

# The smallest absolute tolerance (times the nominal value) of a dummy state in the error test.
# A dummy is solved from equations whose terms are far larger than itself where it passes zero
# (Andrews' squeezer: dependent accelerations through 0 beside terms of 1e4-1e6), so its Newton
# corrections do not shrink below the round-off of those terms: about 3e-14 rad/s^2 RMS, which
# is 0.03 of a weight of 1e-12 where IDAS's convergence test asks for 0.0165 after a Jacobian
# update and a rate below 0.9 after that. Round-off has no rate: the corrector "fails" again at
# every smaller step until h collapses (IDA_CONV_FAIL at t = 0.0087 with 1e-12, 0.0108 with
# 1e-11; 1e-10 runs at every rtol from 1e-10 to 1e-13). The user's atol still holds for the
# states, and every unknown keeps rtol * |value|.
DUMMY_ATOL_FLOOR = 1e-10


def error_controlled(model: CompiledModel, switched: bool = False) -> set[str]:
    """The algebraic unknowns that IDAS's error test controls besides the states: the dummy states
    of the index reduction (positions and velocities demoted from states, e.g. the dependent angles
    of a mechanism) and their first derivatives, named `v` with a `der(v)` in the model or
    `der(v)` of one. Their errors are the states' errors amplified by the constraints (Andrews'
    squeezer at rtol 1e-10: accelerations 4.7 significant digits without, 6.9 with, for 4x the
    steps). Multipliers, forces, derivatives of states and second derivatives `der(der(...))` stay
    out: they follow the states, and their kinks (contact forces) would make IDAS chase them (the
    excavator's only candidates are the angular accelerations der(der(stick.body.phi)) and
    der(der(bucket.body.phi)) of two dummy angles: 11x the steps at rtol 1e-6 with them).

    In a model whose state set may switch, until its first switch (`switched` false), the
    dummies' derivatives only. The monitor keeps the dummy positions well conditioned in the
    states (it switches before one amplifies their error more than 1 / SWITCH_RATIO = 2 times),
    and in the test they cost accuracy (Cartesian pendulum, rtol 1e-10, 10 s: x 2.4e-9 off the
    closed form without, 1.5e-8 with); their rates carry the states' errors times the rates
    (Andrews' squeezer written without state priorities, which never switches, at rtol 1e-10:
    4.7 digits in w1 without them, 6.9 with). Never the candidates of a monitored level: the
    dummy derivatives the monitor chooses among (der(der(q)) in a mechanism; der(y) in a circuit
    whose state set is chosen among node voltages, a capacitor current with the kinks of its
    diodes: the Test Set's transistor amplifier at rtol 1e-6 had 6,333 error-test failures in
    10,762 steps with der(y5) in the test, 19 in 3,231 without). From the first switch on the run
    is integrated at tighter tolerances instead (run_state.switched_factor), the dummies out:
    near a switch their error test is what degrades."""
    if model.state_sets and switched:
        return set()
    states = set(model.state_names)
    known = states | set(model.algebraic_names) | set(model.output_names)
    monitored = {name for level in model.state_sets for name in level["candidates"]}

    def root(name: str) -> str:
        while name.startswith("der(") and name.endswith(")"):
            name = name[4:-1]
        return name

    def kept(name: str) -> bool:
        if name.startswith("der("):
            return name not in monitored
        return not model.state_sets and f"der({name})" in known
    return {n for n in model.algebraic_names
            if root(n) not in states and not n.startswith("der(der(") and kept(n)}
