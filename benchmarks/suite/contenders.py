"""The contenders: dyadc on CasADi's SX virtual machine, dyadc with generated C, scipy solve_ivp.

`solve(rtol, atol) -> (seconds, signals)` on the problem's grid. dyadc's seconds are the wall
time of api.simulate_compiled (consistent initialization, IDAS, evaluation of the signals the
problem asks for); scipy's are the contender's own wall_time_s (solve_ivp plus output
evaluation). Compilation is not included: it is measured separately (compile-time section).
"""
from __future__ import annotations

import dataclasses
import time
import warnings

import numpy as np

from compiler import api

from compiler.cache.c_code import compile_c, on_vm
from compiler.lower import ccodegen
from compiler.errors import DyadError
from suite.problems import Problem, contender_module


class Failed(Exception):
    """The contender could not deliver a solution at this tolerance."""


class DyadcContender:
    """`integrator`: None for the default path (the native IDAS driver where it can run),
    "casadi" or "native", or what makes the run's integrators (compiler.runtime.native.make_integrator,
    named `native`)."""
    def __init__(self, problem: Problem, codegen: str, integrator=None, native: str = ""):
        self.problem = problem
        self.codegen = codegen
        self.integrator = integrator
        self.name = ("dyadc (C)" if codegen == "c" else "dyadc (VM)") if not native \
            else f"dyadc ({codegen.upper()}, {native})"
        began = time.perf_counter()
        self.compilation = api.compile(problem.dyadc_spec, problem.dyadc_lib_dirs)
        self.compile_seconds = time.perf_counter() - began
        self.build_seconds = 0.0
        if codegen == "c":
            began = time.perf_counter()
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", ccodegen.CodegenWarning)
                native = compile_c(self.compilation.model)     # a copy: passes never mutate
            self.build_seconds = time.perf_counter() - began
            if native.metadata.get("codegen") != "c":
                raise Failed("; ".join(str(w.message) for w in caught) or "C code generation unavailable")
            self.compilation = dataclasses.replace(self.compilation, model=native)
        else:
            self.compilation = dataclasses.replace(self.compilation, model=on_vm(self.compilation.model))

    def solve(self, rtol: float, atol: float):
        grid = self.problem.grid
        began = time.perf_counter()
        try:
            # the API's path: runtime.simulate, or segmented IDAS for a dynamic state selection
            result = api.simulate_compiled(self.compilation, self.problem.stop, rtol=rtol, atol=atol,
                                           saveat=grid, progress=False, signals=self.problem.signal_names(),
                                           integrator=self.integrator)
        except DyadError as err:
            raise Failed(str(err).splitlines()[0]) from None
        seconds = time.perf_counter() - began
        self.last_stats = result.stats
        if len(result.time) != len(grid) or not np.allclose(result.time, grid, rtol=1e-12, atol=0):
            raise Failed("output grid differs from the requested one")
        return seconds, self.problem.dyadc_signals(result)


class ScipyContender:
    """`options` replace the problem's scipy options (a variant of the same contender, named
    `variant`); `module` is a contender module of benchmarks/contenders' interface given by path."""
    def __init__(self, problem: Problem, method: str, options: dict | None = None, variant: str = "",
                 module=None):
        self.problem = problem
        self.method = method
        self.name = f"scipy {method}" + (f" ({variant})" if variant else "")
        self.module = module or contender_module(problem.scipy_module)
        self.options = problem.scipy_options if options is None else options

    def solve(self, rtol: float, atol: float):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                output = self.module.run(self.method, rtol, atol, **self.options)
            except (RuntimeError, ValueError, np.linalg.LinAlgError) as err:
                raise Failed(str(err).splitlines()[0]) from None
        return output["wall_time_s"], self.problem.scipy_signals(output)


SCIPY_METHODS = ("Radau", "BDF", "LSODA")


def contenders_for(problem: Problem) -> tuple[list, dict[str, str]]:
    """The contenders that could be set up, and why the others could not."""
    made, unavailable = [], {}
    for codegen in ("vm", "c"):
        try:
            made.append(DyadcContender(problem, codegen))
        except (Failed, DyadError) as err:
            unavailable["dyadc (C)" if codegen == "c" else "dyadc (VM)"] = str(err)
    made.extend(ScipyContender(problem, method) for method in SCIPY_METHODS)
    return made, unavailable
