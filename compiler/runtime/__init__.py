"""Run a compiled model: consistent initialization, IDAS integration, named results.

This module imports only casadi, numpy and the standard library: code generation copies it verbatim
next to every generated model module (as `dyad_runtime.py`), so generated models run without the
compiler installed.
"""
from __future__ import annotations

import difflib
import math
import os
import re
import sys
import tempfile
import time as _time
from typing import Callable, Iterable, Mapping, Sequence

import casadi as ca
import numpy as np

FORMAT_VERSION = 1
PROGRESS_DELAY = 2.0        # seconds of run time before a progress bar appears

# Readable explanations of the IDAS return flags that CasADi reports.
_IDAS_REASONS = {
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


class SimulationFailed(Exception):
    """The solver could not continue. `time_reached` is the last time it got to."""

    def __init__(self, message: str, time_reached: float | None = None, reason: str | None = None):
        super().__init__(message)
        self.time_reached = time_reached
        self.reason = reason


class InitializationFailed(SimulationFailed):
    """No consistent initial point. `worst` lists (residual index, value, label), largest first."""

    def __init__(self, message: str, time_reached: float, worst: list[tuple[int, float, str]]):
        super().__init__(message, time_reached, "inconsistent or unsolvable initial conditions")
        self.worst = worst


class ModelInputError(ValueError):
    """A bad request from the user of a compiled model (unknown parameter or output name, ...)."""


def _did_you_mean(name: str, choices: Iterable[str]) -> str:
    close = difflib.get_close_matches(name, list(choices), n=3, cutoff=0.5)
    return f" (did you mean {', '.join(repr(c) for c in close)}?)" if close else ""


class CompiledModel:
    """The numerical model: CasADi Functions plus the names that give their vectors meaning.

    Functions (all with inputs x, z, p, t unless noted):
      dae     -> (ode, alg)       der(x) = ode, 0 = alg
      init    -> residuals        the initialization system (maybe more rows than unknowns)
      outputs -> values           one row per output name
      params(p_user, override_mask) -> p_full   re-derives dependent parameter defaults
    `state_sets` describes the levels of the dummy-derivative choice that can degrade along a
    trajectory (see `state_selection_quality`); `simulate` integrates the one state set it has and
    stops where that set degrades (the compiler's dynamic simulation switches instead).
    """

    FUNCTION_NAMES = ("dae", "init", "outputs", "params")

    def __init__(self, *, name: str, state_names: Sequence[str], algebraic_names: Sequence[str],
                 parameter_names: Sequence[str], parameter_defaults: Sequence[float],
                 output_names: Sequence[str], x_guess: Sequence[float], z_guess: Sequence[float],
                 dae: ca.Function, init: ca.Function, outputs: ca.Function, params: ca.Function,
                 parameter_tunable: Sequence[bool] | None = None,
                 init_residual_labels: Sequence[str] | None = None,
                 nominals: Mapping[str, float] | None = None,
                 state_sets: Sequence[dict] | None = None,
                 metadata: dict | None = None):
        self.name = name
        self.state_names = list(state_names)
        self.algebraic_names = list(algebraic_names)
        self.parameter_names = list(parameter_names)
        self.parameter_defaults = [float(v) for v in parameter_defaults]
        self.parameter_tunable = ([True] * len(self.parameter_names) if parameter_tunable is None
                                  else [bool(b) for b in parameter_tunable])
        self.output_names = list(output_names)
        self.x_guess = [float(v) for v in x_guess]
        self.z_guess = [float(v) for v in z_guess]
        self.dae = dae
        self.init = init
        self.outputs = outputs
        self.params = params
        self.init_residual_labels = list(init_residual_labels or [])
        self.nominals = {k: float(v) for k, v in (nominals or {}).items()}
        self.state_sets = list(state_sets or [])
        self.metadata = dict(metadata or {})
        self._output_index = {n: i for i, n in enumerate(self.output_names)}
        self._init_jacobian: ca.Function | None = None
        self._algebraic_newton: ca.Function | None = None
        self.native_library: str | None = None
        self._native_dae: ca.Function | None = None
        self.compile_time: float | None = None        # set by the compiler; not serialized

    # -- native (C) code ---------------------------------------------------------------------------
    NATIVE_DAE_NAME = "dyad_dae"

    def use_native_library(self, path: str | os.PathLike | None) -> None:
        """Evaluate the DAE through a compiled shared library (made by the compiler's ccodegen)
        holding `dyad_dae(t, x, z, p, u) -> (ode, alg, quad, zero)` and its Jacobian."""
        self.native_library = None if path is None else os.fspath(path)
        self._native_dae = None

    def native_dae(self) -> ca.Function | None:
        if self.native_library is None:
            return None
        if self._native_dae is None:
            try:
                self._native_dae = ca.external(self.NATIVE_DAE_NAME, self.native_library)
            except RuntimeError as err:
                raise ModelInputError(f"cannot load the compiled model library "
                                      f"{self.native_library}: {str(err).strip().splitlines()[-1]}") \
                    from None
        return self._native_dae

    # -- serialization ---------------------------------------------------------------------------
    def to_dict(self) -> dict:
        return {
            "format_version": FORMAT_VERSION,
            "name": self.name,
            "state_names": self.state_names,
            "algebraic_names": self.algebraic_names,
            "parameter_names": self.parameter_names,
            "parameter_defaults": self.parameter_defaults,
            "parameter_tunable": self.parameter_tunable,
            "output_names": self.output_names,
            "x_guess": self.x_guess,
            "z_guess": self.z_guess,
            "init_residual_labels": self.init_residual_labels,
            "nominals": dict(sorted(self.nominals.items())),
            "state_sets": self.state_sets,
            "metadata": self.metadata,
            "functions": {f: getattr(self, f).serialize() for f in self.FUNCTION_NAMES},
        }

    @classmethod
    def from_dict(cls, data: Mapping) -> "CompiledModel":
        if data.get("format_version") != FORMAT_VERSION:
            raise ModelInputError(f"unsupported compiled-model format {data.get('format_version')!r}"
                                  f" (this runtime reads version {FORMAT_VERSION})")
        functions = {f: ca.Function.deserialize(s) for f, s in data["functions"].items()}
        return cls(name=data["name"], state_names=data["state_names"],
                   algebraic_names=data["algebraic_names"],
                   parameter_names=data["parameter_names"],
                   parameter_defaults=data["parameter_defaults"],
                   parameter_tunable=data.get("parameter_tunable"),
                   output_names=data["output_names"], x_guess=data["x_guess"],
                   z_guess=data["z_guess"],
                   init_residual_labels=data.get("init_residual_labels"),
                   nominals=data.get("nominals"), state_sets=data.get("state_sets"),
                   metadata=data.get("metadata"), **functions)

    # -- parameters --------------------------------------------------------------------------------
    @property
    def parameters(self) -> dict[str, float]:
        return dict(zip(self.parameter_names, self.parameter_defaults))

    def parameter_vector(self, overrides: Mapping[str, float] | None = None) -> np.ndarray:
        """Defaults with `overrides` applied; parameters bound to overridden ones are re-derived."""
        user = np.array(self.parameter_defaults, dtype=float)
        mask = np.zeros(len(user))
        index = {n: i for i, n in enumerate(self.parameter_names)}
        for name, value in (overrides or {}).items():
            if name not in index:
                raise ModelInputError(f"unknown parameter '{name}' in model {self.name}"
                                      + _did_you_mean(name, self.parameter_names))
            i = index[name]
            if not self.parameter_tunable[i]:
                raise ModelInputError(f"parameter '{name}' of model {self.name} is final or "
                                      "constant and cannot be overridden")
            try:
                user[i] = float(value)
            except (TypeError, ValueError):
                raise ModelInputError(f"parameter '{name}': value {value!r} is not a number") from None
            mask[i] = 1.0
        if not len(user):
            return user
        return np.asarray(self.params(user, mask), dtype=float).reshape(-1)

    # -- names -------------------------------------------------------------------------------------
    def output_index(self, name: str) -> int:
        try:
            return self._output_index[name]
        except KeyError:
            raise ModelInputError(f"unknown output '{name}' in model {self.name}"
                                  + _did_you_mean(name, self.output_names)) from None

    def algebraic_newton(self) -> ca.Function:
        """(x, z, p, t) -> (alg, d alg / d z): one Newton step on the algebraic equations."""
        if self._algebraic_newton is None:
            x = ca.SX.sym("x", len(self.state_names))
            z = ca.SX.sym("z", len(self.algebraic_names))
            p = ca.SX.sym("p", len(self.parameter_names))
            t = ca.SX.sym("t")
            _, alg = self.dae(x, z, p, t)
            self._algebraic_newton = ca.Function("alg_newton", [x, z, p, t], [alg, ca.jacobian(alg, z)])
        return self._algebraic_newton

    def init_jacobian(self) -> ca.Function:
        """(x, z, p, t) -> (residuals, d residuals / d [x; z]) by CasADi AD, built once."""
        if self._init_jacobian is None:
            x = ca.SX.sym("x", len(self.state_names))
            z = ca.SX.sym("z", len(self.algebraic_names))
            p = ca.SX.sym("p", len(self.parameter_names))
            t = ca.SX.sym("t")
            r = self.init(x, z, p, t)
            jac = ca.jacobian(r, ca.vertcat(x, z))
            self._init_jacobian = ca.Function("init_jac", [x, z, p, t], [r, jac])
        return self._init_jacobian


# ------------------------------------------------------------------------------------------------
# Consistent initialization
# ------------------------------------------------------------------------------------------------

class InitialPoint:
    def __init__(self, x: np.ndarray, z: np.ndarray, iterations: int, residual: float):
        self.x = x
        self.z = z
        self.iterations = iterations
        self.residual = residual


def _row_scales(jac: np.ndarray) -> np.ndarray:
    """|r_i| / scale_i is how far (in the unknowns) residual i is from being satisfied."""
    norms = np.max(np.abs(jac), axis=1) if jac.size else np.zeros(jac.shape[0])
    return np.where(norms > 1e-300, norms, 1.0)


def _levenberg_marquardt(evaluate: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]],
                         w: np.ndarray, tol: float, max_iterations: int):
    """Least-squares solve of r(w) = 0 with the exact Jacobian. Returns (w, r, jac, iterations)."""
    r, jac = evaluate(w)
    lam = 0.0
    iterations = 0
    while r.size and iterations < max_iterations and np.all(np.isfinite(r)):
        if np.max(_scaled_residual(r, jac, w)) <= tol * 1e-3:
            break
        iterations += 1
        # Row-equilibrate so that residuals in Pa and in m weigh alike; More's column scaling.
        rows = _row_scales(jac)
        jr, rr = jac / rows[:, None], r / rows
        cols = np.sqrt(np.sum(jr * jr, axis=0))
        cols = np.where(cols > 1e-300, cols, 1.0)
        cost = 0.5 * float(rr @ rr)
        accepted = False
        for _ in range(30):
            if lam > 0.0:
                a = np.vstack([jr, np.sqrt(lam) * np.diag(cols)])
                b = np.concatenate([-rr, np.zeros(len(w))])
            else:
                a, b = jr, -rr
            step = _linear_least_squares(a, b)
            w_new = w + step
            r_new, jac_new = evaluate(w_new)
            rr_new = r_new / rows
            cost_new = 0.5 * float(rr_new @ rr_new) if np.all(np.isfinite(r_new)) else math.inf
            predicted = cost - 0.5 * float(np.sum((rr + jr @ step) ** 2))
            if cost_new < cost:
                gain = (cost - cost_new) / predicted if predicted > 0 else 1.0
                lam = 0.0 if gain > 0.75 else lam / 3.0 if gain > 0.25 else max(lam, 1e-6)
                accepted = True
                break
            lam = max(1e-6, 10.0 * lam)
        if not accepted:
            break                                  # a (local) least-squares minimum
        tiny_step = np.max(np.abs(step), initial=0.0) <= 1e-15 * (1.0 + np.max(np.abs(w), initial=0.0))
        w, r, jac = w_new, r_new, jac_new
        if tiny_step:
            break
    return w, r, jac, iterations


def _linear_least_squares(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """min |a s - b|: LU for square, QR for tall full-rank systems (both far cheaper than the SVD),
    the minimum-norm SVD solution when `a` is (nearly) rank-deficient or wide."""
    rows, cols = a.shape
    try:
        if rows == cols > 0:
            s = np.linalg.solve(a, b)
            if np.all(np.isfinite(s)) and \
                    np.linalg.norm(a @ s - b) <= 1e-9 * (np.linalg.norm(b) + 1e-300):
                return s
        elif rows > cols > 0:
            q, r = np.linalg.qr(a)
            diagonal = np.abs(np.diag(r))
            if diagonal.min() > 1e-10 * diagonal.max():
                s = np.linalg.solve(r, q.T @ b)
                if np.all(np.isfinite(s)):
                    return s
    except np.linalg.LinAlgError:
        pass
    return np.linalg.lstsq(a, b, rcond=None)[0]


def _scaled_residual(r: np.ndarray, jac: np.ndarray, w: np.ndarray) -> np.ndarray:
    if not np.all(np.isfinite(r)):
        return np.where(np.isfinite(r), np.abs(r), math.inf)
    return np.abs(r) / _row_scales(jac) / (1.0 + np.max(np.abs(w), initial=0.0))


def consistent_initialization(model: CompiledModel, p: np.ndarray, t0: float, *,
                              tol: float = 1e-10, max_iterations: int = 200) -> InitialPoint:
    """Solve init(x, z, p, t0) = 0 in the least-squares sense (Levenberg–Marquardt, exact Jacobian).

    More residuals than unknowns is fine when they are consistent. Success means every residual,
    divided by the largest entry of its Jacobian row, is below `tol * (1 + |w|_inf)`: a
    Newton-step-sized measure that does not depend on the units of the equation.
    """
    nx = len(model.state_names)
    fun = model.init_jacobian()

    def evaluate(w_: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        r_, j_ = fun(w_[:nx], w_[nx:], p, t0)
        return np.asarray(r_, dtype=float).reshape(-1), np.asarray(ca.densify(j_), dtype=float)

    w0 = np.concatenate([model.x_guess, model.z_guess]).astype(float)
    w, r, jac, iterations = _levenberg_marquardt(evaluate, w0, tol, max_iterations)
    measure = _scaled_residual(r, jac, w)
    if not np.all(measure <= tol):
        order = np.argsort(-np.nan_to_num(measure, nan=math.inf), kind="stable")
        worst = [(int(i), float(r[i]), _label(model, int(i))) for i in order[:5] if measure[i] > tol]
        lines = "\n".join(f"  residual {i} = {value:.6g}: {label}" for i, value, label in worst)
        raise InitializationFailed(
            f"initialization failed at t = {t0:g}: the initial conditions are inconsistent or "
            f"have no solution near the guesses ({iterations} iterations); largest residuals:\n"
            f"{lines}", t0, worst)
    return InitialPoint(w[:nx].copy(), w[nx:].copy(), iterations, float(np.max(measure, initial=0)))


def _label(model: CompiledModel, index: int) -> str:
    labels = model.init_residual_labels
    return labels[index] if index < len(labels) and labels[index] else f"initial residual #{index}"


# ------------------------------------------------------------------------------------------------
# Results
# ------------------------------------------------------------------------------------------------

class Result:
    """A time grid and the named signals on it."""

    def __init__(self, time: np.ndarray, names: Sequence[str], values: np.ndarray,
                 stats: dict | None = None, model_name: str = ""):
        self.time = np.asarray(time, dtype=float)
        self.names = list(names)
        self.values = np.asarray(values, dtype=float).reshape(len(self.names), len(self.time))
        self.stats = dict(stats or {})
        self.model_name = model_name
        self._index = {n: i for i, n in enumerate(self.names)}

    def __getitem__(self, name: str) -> np.ndarray:
        if name == "time":
            return self.time
        try:
            return self.values[self._index[name]]
        except KeyError:
            raise ModelInputError(f"no signal '{name}' in the result of {self.model_name or 'the model'}"
                                  + _did_you_mean(name, self.names)) from None

    def __contains__(self, name: str) -> bool:
        return name == "time" or name in self._index

    def _columns(self, names: Sequence[str] | None) -> list[str]:
        chosen = self.names if names is None else [n for n in names if n != "time"]
        for n in chosen:
            self[n]                                   # validates with a did-you-mean error
        return list(chosen)

    def to_csv(self, path: str | os.PathLike, names: Sequence[str] | None = None) -> None:
        """Write `time` and the chosen signals (%.17g); atomically: no partial file on failure."""
        columns = self._columns(names)
        data = np.vstack([self.time] + [self[n] for n in columns]).T
        header = ",".join(_csv_field(n) for n in ["time"] + columns)
        _atomic_write(path, lambda out: _write_rows(out, header, data))

    def plot(self, path: str | os.PathLike, names: Sequence[str] | None = None,
             title: str | None = None) -> None:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        columns = self._columns(names)
        fig, ax = plt.subplots(figsize=(9, 5))
        for n in columns:
            ax.plot(self.time, self[n], label=n)
        ax.set_xlabel("time [s]")
        ax.set_title(title or self.model_name)
        ax.grid(True, alpha=0.3)
        if columns:
            ax.legend(fontsize="small", loc="best")
        fig.tight_layout()
        try:
            _atomic_write(path, lambda out: fig.savefig(out, format=_plot_format(path)), binary=True)
        finally:
            plt.close(fig)


def _plot_format(path: str | os.PathLike) -> str:
    suffix = os.path.splitext(os.fspath(path))[1].lstrip(".").lower()
    return suffix or "png"


def _csv_field(name: str) -> str:
    if any(c in name for c in ',"\n'):
        return '"' + name.replace('"', '""') + '"'
    return name


def _write_rows(out, header: str, data: np.ndarray) -> None:
    out.write(header + "\n")
    for row in data:
        out.write(",".join("%.17g" % v for v in row) + "\n")


def _atomic_write(path: str | os.PathLike, write: Callable, binary: bool = False) -> None:
    path = os.fspath(path)
    directory = os.path.dirname(os.path.abspath(path))
    os.makedirs(directory, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".", suffix=".tmp",
                               dir=directory)
    try:
        with os.fdopen(fd, "wb" if binary else "w", **({} if binary else {"encoding": "utf-8",
                                                                          "newline": "\n"})) as out:
            write(out)
            out.flush()
            os.fsync(out.fileno())
        # mkstemp makes the file private (0600); give it the mode a plain open() would
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


# ------------------------------------------------------------------------------------------------
# Simulation
# ------------------------------------------------------------------------------------------------

class _Progress:
    """A one-line bar on stderr, shown only once the run has taken longer than `after` seconds."""

    def __init__(self, enabled: bool, start: float, stop: float, after: float | None = None):
        self.enabled = enabled
        self.start, self.stop = start, stop
        self.after = PROGRESS_DELAY if after is None else after
        self.began = _time.perf_counter()
        self.shown = False

    def update(self, t: float) -> None:
        if not self.enabled:
            return
        elapsed = _time.perf_counter() - self.began
        if elapsed < self.after and not self.shown:
            return
        self.shown = True
        frac = 1.0 if self.stop == self.start else (t - self.start) / (self.stop - self.start)
        frac = min(max(frac, 0.0), 1.0)
        width = 30
        bar = "#" * int(round(frac * width))
        sys.stderr.write(f"\r[{bar:<{width}}] t = {t:.4g} / {self.stop:.4g}  {elapsed:6.1f} s")
        sys.stderr.flush()

    def close(self) -> None:
        if self.shown:
            sys.stderr.write("\n")
            sys.stderr.flush()


def _idas_reason(text: str, solver_messages: str = "") -> str:
    """IDAS's flag from CasADi's exception text, explained, plus SUNDIALS's own last message."""
    match = re.search(r'returned "?(IDA_[A-Z_]+)"?', text)
    if match:
        flag = match.group(1)
        reason = f"{flag}: {_IDAS_REASONS.get(flag, 'see the IDAS documentation')}"
    else:
        last = [line.strip() for line in text.strip().splitlines() if line.strip()]
        reason = last[-1] if last else "unknown solver error"
    # SUNDIALS prefixes "At t = ..." in its own (possibly rescaled) time; we report time ourselves.
    said = [re.sub(r"^At t = [^,]*,[ ,]*", "", line.strip()) for line in solver_messages.splitlines()
            if line.strip()]
    return f"{reason} (IDAS: {said[-1]})" if said and said[-1] else reason


class _CapturedStderr:
    """Collect what C code (SUNDIALS) writes to file descriptor 2 during a solver call, so that its
    message becomes part of our error instead of stray text. A no-op where fd 2 is unusable."""

    def __init__(self):
        self.text = ""
        self._saved: int | None = None
        self._file = None

    def __enter__(self) -> "_CapturedStderr":
        try:
            sys.stderr.flush()
            self._file = tempfile.TemporaryFile(mode="w+b")
            self._saved = os.dup(2)
            os.dup2(self._file.fileno(), 2)
        except (OSError, ValueError, AttributeError):
            self._restore()
        return self

    def __exit__(self, *exc) -> None:
        self._restore()

    def _restore(self) -> None:
        if self._saved is not None:
            os.dup2(self._saved, 2)
            os.close(self._saved)
            self._saved = None
        if self._file is not None:
            self._file.seek(0)
            self.text = self._file.read().decode("utf-8", "replace")
            self._file.close()
            self._file = None


def _dae_function(model: CompiledModel, scaled_time: bool) -> ca.Function:
    """The DAE as CasADi's integrator wants it: (t, x, z, p, u) -> (ode, alg, quad, zero).

    With `scaled_time`, t = t_a + t_b * tau (t_a, t_b appended to p), so one integrator over
    tau in [0, 1] serves every chunk of the run. A model compiled to C (`native_dae`) is called
    as an external function whose library also holds its Jacobian.
    """
    native = model.native_dae()
    if native is not None and not scaled_time:
        return native
    sym = ca.SX.sym if native is None else ca.MX.sym
    nx, nz, npar = len(model.state_names), len(model.algebraic_names), len(model.parameter_names)
    x, z, p, t, u = sym("x", nx), sym("z", nz), sym("p", npar), sym("t"), sym("u", 0)
    if scaled_time:
        shift, span = sym("t_a"), sym("t_b")
        p_in, t_model = ca.vertcat(p, shift, span), shift + span * t
    else:
        span, p_in, t_model = 1.0, p, t
    if native is None:
        ode, alg = model.dae(x, z, p, t_model)
    else:
        ode, alg = native(t_model, x, z, p, u)[:2]
    empty = ca.SX(0, 1) if native is None else ca.MX(0, 1)
    return ca.Function("dyad_dae", [t, x, z, p_in, u], [span * ode, alg, empty, empty],
                       ca.dyn_in(), ca.dyn_out())


def _integrator_options(model: CompiledModel, rtol: float, atol, max_steps: int,
                        extra: Mapping | None) -> dict:
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
    if isinstance(atol, Mapping) or model.nominals:
        base = float(atol.get("*", 1e-6)) if isinstance(atol, Mapping) else float(atol)
        per = {n: base * abs(model.nominals.get(n, 1.0)) for n in names}
        if isinstance(atol, Mapping):
            for name, value in atol.items():
                if name == "*":
                    continue
                if name not in per:
                    raise ModelInputError(f"atol given for '{name}', which is not a state or "
                                          f"algebraic unknown of {model.name}"
                                          + _did_you_mean(name, names))
                per[name] = float(value)
        opts["abstolv"] = [per[n] for n in names]
        opts["abstol"] = base
    else:
        opts["abstol"] = float(atol)
    opts.update(extra or {})
    return opts


def output_grid(start: float, stop: float, points: int, saveat: Sequence[float] | None) -> np.ndarray:
    if saveat is not None:
        grid = np.asarray(sorted(float(s) for s in saveat), dtype=float)
        if grid.size == 0:
            raise ModelInputError("saveat is empty")
        if grid[0] < start or grid[-1] > stop:
            raise ModelInputError(f"saveat times must lie in [start, stop] = [{start}, {stop}]")
        if grid[0] > start:
            grid = np.concatenate([[start], grid])
        return np.unique(grid)
    if not stop > start:
        raise ModelInputError(f"stop time {stop} must be greater than start time {start}")
    if points < 2:
        raise ModelInputError(f"points must be at least 2, got {points}")
    return np.linspace(start, stop, int(points))


def simulate(model: CompiledModel, stop: float, *, start: float = 0.0, rtol: float = 1e-6,
             atol: float | Mapping[str, float] = 1e-6, points: int = 501,
             saveat: Sequence[float] | None = None, params: Mapping[str, float] | None = None,
             max_steps: int = 100000, progress: bool | None = None, chunks: int | None = None,
             breakpoints: Sequence[float] | None = None,
             integrator_options: Mapping | None = None) -> Result:
    """Initialize consistently at `start`, integrate with IDAS to `stop`, evaluate all outputs.

    A progress bar on stderr needs the run split into chunks (IDAS restarts at each chunk boundary
    from the consistent point it reached). `progress=None`: on a TTY, the first twentieth of the run
    is timed and, unless the whole run would take more than PROGRESS_DELAY seconds, the rest is
    one IDAS call; off a TTY the run is one call. `progress=True` always chunks and shows the bar
    after PROGRESS_DELAY seconds. `chunks` forces a chunk count.
    `breakpoints` (default: model.metadata["breakpoints"]) are times where the model's inputs
    lose smoothness: IDAS stops exactly there and restarts, instead of stepping across the kink.
    """
    grid = output_grid(float(start), float(stop), points, saveat)
    start, stop = float(grid[0]), float(grid[-1])
    if breakpoints is None:
        breakpoints = model.metadata.get("breakpoints") or []
    inner = sorted({float(b) for b in breakpoints if start < float(b) < stop})
    solve_grid = np.union1d(grid, inner) if inner else grid
    p = model.parameter_vector(params)
    stats: dict = {"compile_time": model.compile_time}

    began = _time.perf_counter()
    point = consistent_initialization(model, p, start)
    stats["init_time"] = _time.perf_counter() - began
    stats["init_iterations"] = point.iterations
    stats["init_residual"] = point.residual

    show = (sys.stderr.isatty() if progress is None else bool(progress))
    n_chunks = int(chunks) if chunks else (min(20, len(solve_grid) - 1) if show else 1)
    adaptive = show and progress is None and not chunks
    began = _time.perf_counter()
    try:
        xs, zs, counters = _integrate(model, solve_grid, p, point, rtol, atol, max_steps, n_chunks,
                                      _Progress(show, start, stop), integrator_options, adaptive,
                                      split_at=[int(i) for i in np.searchsorted(solve_grid, inner)])
    except SimulationFailed as err:
        if not model.state_sets:
            raise
        hint = (f"; this model carries one state set ({', '.join(model.state_names)}), which may have "
                f"degraded before this point: simulate it with dyadc, which switches state sets")
        raise SimulationFailed(str(err) + hint, err.time_reached, (err.reason or "") + hint) from None
    stats["run_time"] = _time.perf_counter() - began
    stats.update(counters)
    if inner:
        keep = np.searchsorted(solve_grid, grid)
        xs, zs = xs[:, keep], zs[:, keep]
    zs = polish_algebraics(model, xs, zs, p, grid)

    began = _time.perf_counter()
    values = _evaluate_outputs(model, xs, zs, p, grid)
    check_state_selection(model, grid, values)
    check_bounds(model, grid, model.output_names, values)
    stats["output_time"] = _time.perf_counter() - began
    return Result(grid, model.output_names, values, stats, model.name)


STATE_SWITCH_RATIO = 0.5       # switch (or stop) when the chosen pivot block is this much worse
_PIVOT_REL_TOL = 1e-8


def pivoted_columns(matrix: np.ndarray, classes: Sequence[Sequence[int]], n_rows: int,
                    rel_tol: float = _PIVOT_REL_TOL) -> list[int]:
    """Pivoted Gram–Schmidt: within each priority class (in order) take the column with the largest
    part orthogonal to the columns already chosen, until `n_rows` are chosen. This is the
    numerical dummy-derivative choice of the compiler, also used to monitor it while integrating."""
    matrix = np.asarray(matrix, dtype=float)
    scale = max(1.0, float(np.max(np.abs(matrix)))) if matrix.size else 1.0
    if matrix.shape[0] == 1:
        # one constraint row (a pendulum rod): the largest entry of the first usable class
        row = np.abs(matrix[0])
        for members in classes:
            if members:
                j = max(members, key=lambda k: row[k])
                if row[j] > rel_tol * scale:
                    return [j]
        return []
    basis = np.zeros((matrix.shape[0], 0))
    chosen: list[int] = []
    for members in classes:
        remaining = list(members)
        while remaining and len(chosen) < n_rows:
            best, best_norm, best_vec = None, 0.0, None
            for j in remaining:
                col = matrix[:, j]
                residual = col - basis @ (basis.T @ col) if basis.shape[1] else col.copy()
                norm = float(np.linalg.norm(residual))
                if norm > best_norm:
                    best, best_norm, best_vec = j, norm, residual
            if best is None or best_norm <= rel_tol * scale:
                break
            basis = np.column_stack([basis, best_vec / best_norm])
            chosen.append(best)
            remaining.remove(best)
        if len(chosen) == n_rows:
            break
    return chosen


def state_selection_quality(state_sets: Sequence[Mapping], column: np.ndarray) -> tuple[float, int]:
    """How good the model's state choice is at one output point: min over the monitored levels
    of sigma_min(chosen pivot block) / sigma_min(block that pivoting would choose here), 1 where
    the choice is the best one. Each level is {"rows", "candidates", "chosen", "classes",
    "entries"}: the level's Jacobian entries are outputs `entries` (row-major). Returns the
    quality and the worst level's index."""
    quality, worst = 1.0, -1
    for k, level in enumerate(state_sets):
        rows, n_cand = int(level["rows"]), len(level["candidates"])
        matrix = np.asarray(column, dtype=float)[level["entries"]].reshape(rows, n_cand)
        best = pivoted_columns(matrix, level["classes"], rows)
        current = list(level["chosen"])
        if sorted(best) == sorted(current) or len(best) < rows:
            continue
        best_sigma = _smallest_singular(matrix[:, best])
        if best_sigma > 0:
            ratio = _smallest_singular(matrix[:, current]) / best_sigma
            if ratio < quality:
                quality, worst = ratio, k
    return quality, worst


def _smallest_singular(block: np.ndarray) -> float:
    return float(np.linalg.svd(block, compute_uv=False)[-1]) if block.size else 0.0


def check_state_selection(model: CompiledModel, grid: np.ndarray, values: np.ndarray) -> None:
    """A model compiled for one state set (a generated module, say) is only valid while that set
    stays well conditioned: stop where pivoting would clearly choose another one."""
    if not model.state_sets:
        return
    for k in range(values.shape[1]):
        quality, worst = state_selection_quality(model.state_sets, values[:, k])
        if quality < STATE_SWITCH_RATIO:
            level = model.state_sets[worst]
            dummies = ", ".join(level["candidates"][j] for j in level["chosen"])
            reason = (f"its state set ({', '.join(model.state_names)}) degrades here (the pivot block of "
                      f"the dummy derivatives {dummies} is {quality:.2g} times as well conditioned as "
                      f"another choice); this model carries one state set: simulate it with dyadc, "
                      f"which switches state sets")
            raise SimulationFailed(f"simulation of {model.name} stopped at t = {grid[k]:.10g}: {reason}",
                                   float(grid[k]), reason)


def check_bounds(model: CompiledModel, grid: np.ndarray, names: Sequence[str], values: np.ndarray) -> None:
    """A variable outside its declared min/max (a chamber volume below zero, say) means the model
    has left the domain where its equations mean anything: stop instead of returning nonsense."""
    bounds = model.metadata.get("bounds") or {}
    if not bounds:
        return
    index = {n: i for i, n in enumerate(names)}
    first = None
    for name, limits in bounds.items():
        if name not in index:
            continue
        row = values[index[name]]
        for key, bad in (("min", lambda v, b: v < b), ("max", lambda v, b: v > b)):
            if key not in limits:
                continue
            bound = float(limits[key])
            slack = 1e-12 + 1e-9 * abs(bound)
            hits = np.nonzero(bad(row, bound - slack if key == "min" else bound + slack))[0]
            if hits.size and (first is None or hits[0] < first[0]):
                first = (int(hits[0]), name, key, bound, float(row[hits[0]]))
    if first is not None:
        k, name, key, bound, value = first
        reason = f"{name} = {value:.6g} is outside its declared {key} = {bound:g}"
        raise SimulationFailed(f"simulation of {model.name} left the model's domain at t = {grid[k]:.10g}: "
                               f"{reason}", float(grid[k]), reason)


def polish_algebraics(model: CompiledModel, xs: np.ndarray, zs: np.ndarray, p: np.ndarray,
                      grid: np.ndarray, iterations: int = 2) -> np.ndarray:
    """IDAS interpolates z between its steps, so at output times the algebraic equations hold only
    to the interpolation error. With the states fixed, a couple of Newton steps on 0 = alg(x, z)
    make the outputs satisfy them to round-off (the constraint of a mechanism to ~1e-15)."""
    nz, n = zs.shape
    if nz == 0 or n == 0:
        return zs
    newton = model.algebraic_newton().map(n)
    pp = np.repeat(p.reshape(-1, 1), n, axis=1)
    z = zs.copy()
    for _ in range(iterations):
        r, jac = newton(xs, z, pp, grid.reshape(1, -1))
        r = np.asarray(r, dtype=float).reshape(nz, n)
        jac = np.asarray(ca.densify(jac), dtype=float).reshape(nz, n, nz).transpose(1, 0, 2)
        try:
            step = np.linalg.solve(jac, r.T[:, :, None])[:, :, 0].T
        except np.linalg.LinAlgError:
            return z
        candidate = z - step
        r_new = np.asarray(newton(xs, candidate, pp, grid.reshape(1, -1))[0], dtype=float).reshape(nz, n)
        better = np.all(np.isfinite(r_new), axis=0) & (np.abs(r_new).max(axis=0) <= np.abs(r).max(axis=0))
        z[:, better] = candidate[:, better]
    return z


def _evaluate_outputs(model: CompiledModel, xs: np.ndarray, zs: np.ndarray, p: np.ndarray,
                      grid: np.ndarray) -> np.ndarray:
    n = len(grid)
    if not model.output_names:
        return np.zeros((0, n))
    mapped = model.outputs.map(n)
    out = mapped(xs, zs, np.repeat(p.reshape(-1, 1), n, axis=1), grid.reshape(1, -1))
    return np.asarray(out, dtype=float).reshape(len(model.output_names), n)


_COUNTERS = {"nsteps": "steps", "nfevals": "residual_evaluations", "n_call_jacF": "jacobian_evaluations",
             "nlinsetups": "linear_solver_setups", "netfails": "error_test_failures",
             "nniters": "newton_iterations", "nncfails": "newton_convergence_failures"}


def _make_integrator(model: CompiledModel, dae: ca.Function, t0: float, grid: list[float],
                     opts: dict) -> ca.Function:
    try:
        return ca.integrator("dyad_idas", "idas", dae, t0, grid, opts)
    except RuntimeError as err:
        reason = str(err).strip().splitlines()[-1]
        raise SimulationFailed(f"cannot set up IDAS for {model.name}: {reason}", t0, reason) from None


def _integrate(model, grid, p, point, rtol, atol, max_steps, n_chunks, progress, extra,
               adaptive=False, split_at=()):
    """Integrate over `grid` in `n_chunks` IDAS calls, also stopping at the grid indices `split_at`.
    With `adaptive`, the first chunk is timed and, when the whole run would end before a progress
    bar is due, the rest is one call per breakpoint segment."""
    nx, nz = len(model.state_names), len(model.algebraic_names)
    n = len(grid)
    xs = np.empty((nx, n))
    zs = np.empty((nz, n))
    xs[:, 0], zs[:, 0] = point.x, point.z
    counters = {v: 0 for v in _COUNTERS.values()}
    counters["chunks"] = 0
    opts = _integrator_options(model, rtol, atol, max_steps, extra)
    if nx == 0:
        if nz:
            _solve_static(model, grid, p, zs, counters, progress)
        return xs, zs, counters

    bounds = [int(v) for v in
              np.linspace(0, n - 1, max(1, min(n_chunks, n - 1)) + 1).round().astype(int)]
    splits = sorted({int(i) for i in split_at if 0 < int(i) < n - 1})
    bounds = sorted(set(bounds) | set(splits))
    uniform = (len(bounds) > 2 and not splits
               and np.allclose(np.diff(grid), grid[1] - grid[0], rtol=1e-9, atol=0))
    cache: dict[int, ca.Function] = {}
    x, z = point.x, point.z
    progress.update(grid[0])
    began = _time.perf_counter()
    segments = list(zip(bounds[:-1], bounds[1:]))
    try:
        while segments:
            a, b = segments.pop(0)
            x, z = _integrate_segment(model, grid, a, b, x, z, p, opts, uniform, cache, xs, zs,
                                      counters)
            progress.update(grid[b])
            if adaptive and a == 0 and segments:
                projected = (_time.perf_counter() - began) * (n - 1) / b
                if projected < progress.after:
                    rest = [b] + [i for i in splits if i > b] + [n - 1]
                    segments, uniform = list(zip(rest[:-1], rest[1:])), False
    finally:
        progress.close()
    return xs, zs, counters


def _integrate_segment(model, grid, a, b, x, z, p, opts, scaled, cache, xs, zs, counters):
    """One IDAS call from grid[a] to grid[b], filling xs and zs; returns the final (x, z)."""
    nx, nz = xs.shape[0], zs.shape[0]
    if scaled:
        # tau grid k/m (k = 1..m) reused by every chunk with m intervals.
        m = b - a
        if m not in cache:
            cache[m] = _make_integrator(model, _dae_function(model, scaled_time=True), 0.0,
                                        [k / m for k in range(1, m + 1)], opts)
        solver = cache[m]
        pp = np.concatenate([p, [grid[a], grid[b] - grid[a]]])
    else:
        xdot = np.asarray(model.dae(x, z, p, grid[a])[0], dtype=float).reshape(-1)
        solver = _make_integrator(model, _dae_function(model, scaled_time=False), float(grid[a]),
                                  [float(v) for v in grid[a + 1:b + 1]],
                                  dict(opts, init_xdot=list(xdot)))
        pp = p
    try:
        with _CapturedStderr() as messages:
            sol = solver(x0=x, z0=z, p=pp)
    except RuntimeError as err:
        reached = solver.stats().get("tcur", math.nan)
        if scaled and math.isfinite(reached):
            reached = grid[a] + (grid[b] - grid[a]) * reached
        reason = _idas_reason(str(err), messages.text)
        raise SimulationFailed(f"simulation of {model.name} failed at t = {reached:.10g}: "
                               f"{reason}", float(reached), reason) from None
    _accumulate(counters, solver.stats())
    counters["chunks"] += 1
    xs[:, a + 1:b + 1] = np.asarray(sol["xf"], dtype=float).reshape(nx, b - a)
    zs[:, a + 1:b + 1] = np.asarray(sol["zf"], dtype=float).reshape(nz, b - a)
    return xs[:, b], zs[:, b]


def _solve_static(model: CompiledModel, grid: np.ndarray, p: np.ndarray, zs: np.ndarray,
                  counters: dict, progress: _Progress) -> None:
    """No states: IDAS has nothing to integrate, so solve 0 = alg(z, p, t) at every output time,
    each solve starting from the previous solution."""
    z_sym = ca.SX.sym("z", len(model.algebraic_names))
    t_sym = ca.SX.sym("t")
    p_sym = ca.SX.sym("p", len(model.parameter_names))
    alg = model.dae(ca.SX(0, 1), z_sym, p_sym, t_sym)[1]
    fun = ca.Function("alg_jac", [z_sym, p_sym, t_sym], [alg, ca.jacobian(alg, z_sym)])
    tol = 1e-12
    try:
        for k in range(1, len(grid)):
            def evaluate(z_: np.ndarray, t_=grid[k]) -> tuple[np.ndarray, np.ndarray]:
                r_, j_ = fun(z_, p, t_)
                return np.asarray(r_, dtype=float).reshape(-1), np.asarray(ca.densify(j_), dtype=float)
            z, r, jac, iterations = _levenberg_marquardt(evaluate, zs[:, k - 1].copy(), tol, 100)
            counters["newton_iterations"] += iterations
            if not np.all(_scaled_residual(r, jac, z) <= tol * 1e3):
                reason = "the algebraic equations have no solution near the previous one"
                raise SimulationFailed(f"simulation of {model.name} failed at t = {grid[k]:.10g}: "
                                       f"{reason}", float(grid[k - 1]), reason)
            zs[:, k] = z
            counters["steps"] += 1
            progress.update(grid[k])
    finally:
        progress.close()


def _accumulate(counters: dict, st: Mapping) -> None:
    for key, name in _COUNTERS.items():
        value = st.get(key)
        if isinstance(value, (int, float)) and math.isfinite(value):
            counters[name] += int(value)
