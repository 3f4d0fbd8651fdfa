"""The compiled model: the one hand-over from the compiler to the runtime.

CasADi Functions plus the names that give their vectors meaning, defaults, bounds, state sets and
events; serializable to plain data (`to_dict`/`from_dict`) so that generated modules and sweep
workers rebuild it without the compiler.
"""
from __future__ import annotations

import copy
import os
from typing import Mapping, Sequence

import casadi as ca
import numpy as np

from .errors import ModelInputError, did_you_mean

FORMAT_VERSION = 5                  # 3: the state-set variants (`variants`); 4: their alias folds;
_READABLE_FORMATS = (1, 2, 3, 4, 5)  # 5: the system every state set is made from (`universal`)


class CompiledModel:
    """Functions (inputs x, z, p, t unless noted):
      dae     -> (ode, alg)       der(x) = ode, 0 = alg
      init    -> residuals        the initialization system (maybe more rows than unknowns)
      outputs -> values           one row per output name
      params(p_user, override_mask) -> p_full   re-derives dependent parameter defaults
      events  -> zero             optional: one row per relation of the model that depends on the
                                  unknowns (a state event where it changes sign), `event_labels`
      time_events(p) -> (offset, period)  optional: times where a time-only expression is
                                  non-smooth: offset + k * period for k = 0, 1, ... (period 0: once)
    `state_sets` lists the levels of the dummy-derivative choice that can degrade along a
    trajectory (see state_sets.py); `metadata["bounds"]` the declared min/max of outputs.
    `variants` maps each other state set (its dummy derivatives, a frozenset of names) to its
    model, every one derived at compile time (variants.py switches among them). A model with more
    state sets than are derived one by one carries instead `universal`: its index-1 system with
    every unknown algebraic, from which universal.py makes the model of any state set.
    """

    FUNCTION_NAMES = ("dae", "init", "outputs", "params")
    OPTIONAL_FUNCTIONS = ("events", "time_events")
    NATIVE_DAE_NAME = "dyad_dae"
    # the per-point functions of (x, z, p, t) in the same library (compiler/lower/ccodegen.py)
    NATIVE_FUNCTION_NAMES = {"outputs": "dyad_outputs", "algebraic_newton": "dyad_alg_newton",
                             "algebraic_residual": "dyad_alg_residual", "polished_outputs": "dyad_polished_outputs"}

    def __init__(self, *, name: str, state_names: Sequence[str], algebraic_names: Sequence[str],
                 parameter_names: Sequence[str], parameter_defaults: Sequence[float],
                 output_names: Sequence[str], x_guess: Sequence[float], z_guess: Sequence[float],
                 dae: ca.Function, init: ca.Function, outputs: ca.Function, params: ca.Function,
                 parameter_tunable: Sequence[bool] | None = None,
                 init_residual_labels: Sequence[str] | None = None,
                 nominals: Mapping[str, float] | None = None,
                 state_sets: Sequence[dict] | None = None,
                 metadata: dict | None = None,
                 events: ca.Function | None = None, event_labels: Sequence[str] | None = None,
                 time_events: ca.Function | None = None,
                 time_event_labels: Sequence[str] | None = None,
                 variants: Mapping[frozenset, "CompiledModel"] | None = None,
                 universal: "CompiledModel | None" = None):
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
        self.events = events
        self.event_labels = list(event_labels or [])
        self.time_events = time_events
        self.time_event_labels = list(time_event_labels or [])
        self.init_residual_labels = list(init_residual_labels or [])
        self.nominals = {k: float(v) for k, v in (nominals or {}).items()}
        self.state_sets = list(state_sets or [])
        self.metadata = dict(metadata or {})
        self.variants = dict(variants or {})
        self.universal = universal
        self.native_library: str | None = None
        self.compile_time: float | None = None        # set by the compiler; not serialized
        self._output_index = {n: i for i, n in enumerate(self.output_names)}
        self._derived: dict = {}                       # functions built from the above, on demand

    def replace(self, **changes) -> "CompiledModel":
        """A copy with some attributes changed (passes return new models, never mutate one)."""
        new = copy.copy(self)
        new._derived = {}
        for key, value in changes.items():
            if not hasattr(self, key):
                raise AttributeError(f"CompiledModel has no attribute {key!r}")
            setattr(new, key, value)
        new._output_index = {n: i for i, n in enumerate(new.output_names)}
        return new

    def __getstate__(self) -> dict:
        """Pickled and deep-copied without what was derived (IDAS objects, evaluators, a lock):
        it is rebuilt on demand."""
        state = dict(self.__dict__)
        state["_derived"] = {}
        return state

    @property
    def sizes(self) -> tuple[int, int, int]:
        return len(self.state_names), len(self.algebraic_names), len(self.parameter_names)

    # -- native (C) code ---------------------------------------------------------------------------
    def with_native_library(self, path: str | os.PathLike | None) -> "CompiledModel":
        """The same model evaluating its DAE through a shared library made by the compiler's C code
        generation, holding `dyad_dae(t, x, z, p, u) -> (ode, alg, quad, zero)` and its Jacobian."""
        return self.replace(native_library=None if path is None else os.fspath(path))

    def native_dae(self) -> ca.Function | None:
        if self.native_library is None:
            return None
        if "native" not in self._derived:
            try:
                self._derived["native"] = ca.external(self.NATIVE_DAE_NAME, self.native_library)
            except RuntimeError as err:
                raise ModelInputError(f"cannot load the compiled model library "
                                      f"{self.native_library}: {str(err).strip().splitlines()[-1]}") \
                    from None
        return self._derived["native"]

    def native_function(self, role: str) -> ca.Function | None:
        """The C version of one of NATIVE_FUNCTION_NAMES' functions from the model's library, or
        None: no library, or one built before libraries held it (the VM's function is used then)."""
        if self.native_dae() is None:
            return None
        key = ("native", role)
        if key not in self._derived:
            try:
                self._derived[key] = ca.external(self.NATIVE_FUNCTION_NAMES[role], self.native_library)
            except RuntimeError:
                self._derived[key] = None
        return self._derived[key]

    # -- serialization ---------------------------------------------------------------------------
    def to_dict(self) -> dict:
        functions = {f: getattr(self, f).serialize() for f in self.FUNCTION_NAMES}
        functions.update({f: getattr(self, f).serialize() for f in self.OPTIONAL_FUNCTIONS
                          if getattr(self, f) is not None})
        return {
            # the oldest format that holds the model: a runtime that predates `universal` reads the rest
            "format_version": FORMAT_VERSION if self.universal is not None else 4,
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
            "event_labels": self.event_labels,
            "time_event_labels": self.time_event_labels,
            "metadata": self.metadata,
            "functions": functions,
            **({"variants": [{"dummies": sorted(key), "model": model.to_dict()}
                             for key, model in sorted(self.variants.items(), key=lambda kv: sorted(kv[0]))]}
               if self.variants else {}),
            **({"universal": self.universal.to_dict()} if self.universal is not None else {}),
        }

    @classmethod
    def from_dict(cls, data: Mapping) -> "CompiledModel":
        if data.get("format_version") not in _READABLE_FORMATS:
            raise ModelInputError(f"unsupported compiled-model format {data.get('format_version')!r}"
                                  f" (this runtime reads versions {_READABLE_FORMATS})")
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
                   event_labels=data.get("event_labels"),
                   time_event_labels=data.get("time_event_labels"),
                   metadata=data.get("metadata"),
                   variants={frozenset(v["dummies"]): cls.from_dict(v["model"])
                             for v in data.get("variants", ())},
                   universal=cls.from_dict(data["universal"]) if "universal" in data else None,
                   **functions)

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
                                      + did_you_mean(name, self.parameter_names))
            i = index[name]
            if not self.parameter_tunable[i]:
                raise ModelInputError(f"parameter '{name}' of model {self.name} is final or "
                                      "constant and cannot be overridden")
            try:
                user[i] = float(value)
            except (TypeError, ValueError):
                raise ModelInputError(f"parameter '{name}': value {value!r} is not a number") from None
            if not np.isfinite(user[i]):
                raise ModelInputError(f"parameter '{name}': value {value!r} is not finite")
            mask[i] = 1.0
        if not len(user):
            return user
        return np.asarray(self.params(user, mask), dtype=float).reshape(-1)

    def named_parameters(self, vector) -> dict[str, float]:
        """The model's own parameters by name with their values in `vector` (a run's): without the
        internal ones the compiler adds (the event clock, relation locks; names `__...`)."""
        return {name: float(value) for name, value in zip(self.parameter_names, vector)
                if not name.startswith("__")}

    # -- names -------------------------------------------------------------------------------------
    def output_index(self, name: str) -> int:
        try:
            return self._output_index[name]
        except KeyError:
            raise ModelInputError(f"unknown output '{name}' in model {self.name}"
                                  + did_you_mean(name, self.output_names)) from None

    # -- functions derived once per model ------------------------------------------------------------
    def symbols(self) -> tuple[ca.SX, ca.SX, ca.SX, ca.SX]:
        nx, nz, npar = self.sizes
        return ca.SX.sym("x", nx), ca.SX.sym("z", nz), ca.SX.sym("p", npar), ca.SX.sym("t")

    def derived(self, key: str, build):
        """A function built from this model's functions once, then kept (e.g. the Jacobian of the
        initialization system, the mapped output function)."""
        if key not in self._derived:
            self._derived[key] = build()
        return self._derived[key]

    def algebraic_newton(self) -> ca.Function:
        """(x, z, p, t) -> (alg, d alg / d z): one Newton step on the algebraic equations."""
        def build():
            x, z, p, t = self.symbols()
            _, alg = self.dae(x, z, p, t)
            return ca.Function("alg_newton", [x, z, p, t], [alg, ca.jacobian(alg, z)])
        return self.derived("algebraic_newton", build)

    def init_jacobian(self) -> ca.Function:
        """(x, z, p, t) -> (residuals, d residuals / d [x; z]) by CasADi AD."""
        def build():
            x, z, p, t = self.symbols()
            r = self.init(x, z, p, t)
            return ca.Function("init_jac", [x, z, p, t], [r, ca.jacobian(r, ca.vertcat(x, z))])
        return self.derived("init_jacobian", build)
