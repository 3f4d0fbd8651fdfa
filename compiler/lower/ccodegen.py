"""Compiled C (the code runs take by default; `--codegen c`): the C source of a model's DAE, its
Jacobian and the functions the runtime evaluates at every output point, and the C compiler runs
that turn it into a shared library.

CasADi's CodeGenerator writes `dyad_dae(t, x, z, p, u) -> (ode, alg, quad, zero)` and its Jacobian
`jac_dyad_dae`, which `casadi.external` finds in the same library by name: all IDAS needs. The
Jacobian is taken with respect to x and z only (IDAS uses nothing else; the t and p blocks are
structurally zero), so anything that needs derivatives in t or p (sensitivities) must use the
model's CasADi functions instead. The per-point functions (`pointwise_functions`: the outputs and
the polishing's Newton step on the algebraic equations) run in C too. Names of the model never
reach the C code: every identifier in it is a fixed one of ours (dyad_dae, x, z, p, t). Why these
choices and the flags (-Og): docs/cache.md, "C code". The libraries are built and kept by
compiler/cache/c_code.py.

Every function the library holds is listed once, in `library_functions`: `c_source` writes them
as one C file (for those that want one, as an FMU does); `c_units` writes them as two files that
two compiler processes build at once (the DAE's Jacobian is about half of the build), linked by
`compile_units` into one library with the same exported functions.
"""
from __future__ import annotations

import functools
import os
import subprocess
import tempfile
from pathlib import Path

import casadi as ca

from compiler.runtime import CompiledModel, polishing, watches
from compiler.runtime.native_build import find_compiler  # noqa: F401  (the one rule, used as ccodegen.find_compiler)

COMPILE_FLAGS = ["-Og", "-fPIC"]
LINK_FLAGS = ["-shared"]
FLAGS = COMPILE_FLAGS + LINK_FLAGS          # one file compiled and linked in one go
COMPILE_TIMEOUT = 600
SOURCE_NAME = "dyad_dae.c"
LIBRARY_NAME = "dyad_dae.so"
# Jacobians of at least this many instructions are compiled in a process of their own (at about
# 24 characters of C each, gcc takes 0.15-0.2 s for 1500; a file of a small model costs 0.08 s
# of CPU in one process, 0.11 s in two)
SPLIT_FROM = 1500
_DIFFERENTIATED_INPUTS = ("x", "z")


class CodegenWarning(UserWarning):
    pass


def dae_function(model: CompiledModel) -> ca.Function:
    """The model's DAE with the signature CasADi integrators take (t, x, z, p, u)."""
    nx, nz, npar = len(model.state_names), len(model.algebraic_names), len(model.parameter_names)
    x, z, p, t, u = (ca.SX.sym("x", nx), ca.SX.sym("z", nz), ca.SX.sym("p", npar), ca.SX.sym("t"),
                     ca.SX.sym("u", 0))
    ode, alg = model.dae(x, z, p, t)
    return ca.Function(CompiledModel.NATIVE_DAE_NAME, [t, x, z, p, u],
                       [ode, alg, ca.SX(0, 1), ca.SX(0, 1)], ca.dyn_in(), ca.dyn_out())


def state_jacobian(dae: ca.Function) -> ca.Function:
    """`jac_<dae>` with the signature CasADi looks for (the inputs, then the nominal outputs; one
    output `jac_<out>_<in>` per pair) whose blocks in t, p and u are structurally zero."""
    inputs = [dae.sx_in(i) for i in range(dae.n_in())]
    outputs = dae(*inputs)
    nominal = [ca.SX.sym("out_" + dae.name_out(j), dae.sparsity_out(j)) for j in range(dae.n_out())]
    blocks, names = [], []
    for j in range(dae.n_out()):
        for i in range(dae.n_in()):
            names.append(f"jac_{dae.name_out(j)}_{dae.name_in(i)}")
            blocks.append(ca.jacobian(outputs[j], inputs[i]) if dae.name_in(i) in _DIFFERENTIATED_INPUTS
                          else ca.SX(outputs[j].numel(), inputs[i].numel()))
    return ca.Function("jac_" + dae.name(), inputs + nominal, blocks,
                       dae.name_in() + ["out_" + n for n in dae.name_out()], names)


def pointwise_functions(model: CompiledModel) -> list[ca.Function]:
    """The functions of (x, z, p, t) the runtime evaluates at every output point, under the names
    `CompiledModel.native_function` looks up: every output, and what the polishing of z uses
    (compiler/runtime/polishing.py: its one-function Newton step for a small algebraic system,
    else the Newton function and the residual); the same expressions as on the VM."""
    x, z, p, t = model.symbols()
    alg = model.dae(x, z, p, t)[1]
    names = CompiledModel.NATIVE_FUNCTION_NAMES
    if 0 < z.numel() <= polishing.FUSED_UP_TO:
        return [polishing.polished_outputs_function(model, None, names["polished_outputs"])]
    functions = [ca.Function(names["outputs"], [x, z, p, t], [model.outputs(x, z, p, t)])]
    if z.numel() == 0:
        return functions
    return functions + [ca.Function(names["algebraic_newton"], [x, z, p, t], [alg, ca.jacobian(alg, z)]),
                        ca.Function(names["algebraic_residual"], [x, z, p, t], [alg])]


def watch_functions(model: CompiledModel) -> list[ca.Function]:
    """`dyad_watch(x, z, p, t, atol)`: the zero functions a run watches (runtime/watches.py, the
    same rows in the same order), for the root finding of the native IDAS driver (compiler/runtime/native),
    which calls it from C; `atol` is an input because the bounds' slack depends on the run's
    absolute tolerance. None of it for a model that watches nothing."""
    x, z, p, t = symbols = model.symbols()
    atol = ca.SX.sym("atol")
    rows, labels = watches.watched_rows(model, symbols, atol)
    return [ca.Function("dyad_watch", [x, z, p, t, atol], [rows])] if labels else []


def library_functions(model: CompiledModel) -> list[ca.Function]:
    """Every function of the model's C library, the DAE first (the one place to add one)."""
    dae = dae_function(model)
    return [dae, state_jacobian(dae), *pointwise_functions(model), *watch_functions(model)]


def _generated(name: str, functions: list[ca.Function]) -> str:
    with tempfile.TemporaryDirectory(prefix="dyadc-cg-") as tmp:
        generator = ca.CodeGenerator(name, {"with_header": False})
        for function in functions:
            generator.add(function)
        generator.generate(tmp + os.sep)        # the prefix is the output directory
        return (Path(tmp) / f"{name}.c").read_text(encoding="utf-8")


def c_source(model: CompiledModel) -> str:
    """The whole library as one C file."""
    return _generated(Path(SOURCE_NAME).stem, library_functions(model))


def c_units(model: CompiledModel) -> dict[str, str]:
    """The library as C files built side by side: {file name: source}. The DAE's Jacobian is one
    file, every other function the other (each file's helpers are static: no name clashes); one
    file when the Jacobian is small (a second compiler process then costs more than it saves)."""
    functions = library_functions(model)
    is_jacobian = [f.name() == "jac_" + CompiledModel.NATIVE_DAE_NAME for f in functions]
    if sum(f.n_instructions() for f, j in zip(functions, is_jacobian) if j) < SPLIT_FROM:
        return {SOURCE_NAME: _generated(Path(SOURCE_NAME).stem, functions)}
    units = {"dyad_jacobian": [f for f, j in zip(functions, is_jacobian) if j],
             "dyad_functions": [f for f, j in zip(functions, is_jacobian) if not j]}
    return {f"{name}.c": _generated(name, group) for name, group in units.items() if group}


@functools.lru_cache(maxsize=None)
def compiler_identity(compiler: str) -> str:
    """The first line of `compiler --version` (what a library built by it depends on); asked once
    per process and compiler."""
    try:
        done = subprocess.run([compiler, "--version"], capture_output=True, text=True, timeout=30)
        return done.stdout.splitlines()[0] if done.stdout else compiler
    except (OSError, subprocess.SubprocessError):
        return compiler


def compile_library(source: str, compiler: str, folder: Path) -> Path:
    """Compile `source` into a shared library inside `folder`."""
    return compile_units({SOURCE_NAME: source}, compiler, folder)


def compile_units(units: dict[str, str], compiler: str, folder: Path) -> Path:
    """Compile each C file of `units` ({file name: source}) in a process of its own, all at once,
    and link them into one shared library inside `folder`.

    Paths are absolute and the compiler runs in this process's folder: no `cwd=`, whose chdir in
    the child failed now and then with ENOENT while the suite's processes shared a cache folder.
    The library's bytes still do not depend on the folder (gcc records the file's base name)."""
    folder = Path(folder).resolve()
    objects = []
    for name, source in units.items():
        (folder / name).write_text(source, encoding="utf-8")
        objects.append(str(folder / Path(name).with_suffix(".o").name))
    running = [subprocess.Popen([compiler, *COMPILE_FLAGS, "-c", str(folder / name), "-o", obj],
                                stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
               for name, obj in zip(units, objects)]
    failures = [_finished(process) for process in running]
    failure = next((f for f in failures if f), None)
    library = folder / LIBRARY_NAME
    if failure is None:
        failure = _finished(subprocess.Popen([compiler, *LINK_FLAGS, *objects, "-o", str(library), "-lm"],
                                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True))
    if failure:
        raise RuntimeError(f"{Path(compiler).name} failed: {failure[-2000:]}")
    return library


def _finished(process: subprocess.Popen) -> str | None:
    """None when `process` succeeds, else its error output (it is killed after COMPILE_TIMEOUT)."""
    try:
        _, errors = process.communicate(timeout=COMPILE_TIMEOUT)
    except subprocess.TimeoutExpired:
        process.kill()
        process.communicate()
        return f"no result after {COMPILE_TIMEOUT} s"
    return None if process.returncode == 0 else (errors.strip() or f"exit status {process.returncode}")
