"""`--codegen c`: the C source of a model's DAE, its Jacobian and the functions the runtime
evaluates at every output point, and the C compiler run that turns it into a shared library.

CasADi's CodeGenerator writes `dyad_dae(t, x, z, p, u) -> (ode, alg, quad, zero)` and its Jacobian
`jac_dyad_dae`, which `casadi.external` finds in the same library by name: all IDAS needs. The
Jacobian is taken with respect to x and z only (IDAS uses nothing else; the t and p blocks are
structurally zero), so anything that needs derivatives in t or p (sensitivities) must use the
model's CasADi functions instead. The per-point functions (`pointwise_functions`: the outputs and
the polishing's Newton step on the algebraic equations) run in C too. Names of the model never
reach the C code: every identifier in it is a fixed one of ours (dyad_dae, x, z, p, t). Why these
choices and the flags (-O1): docs/cache.md, "`--codegen c`". The libraries are built and kept by
compiler/cache/c_code.py.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
from pathlib import Path

import casadi as ca

from compiler.runtime import CompiledModel, polishing, watches

FLAGS = ["-O1", "-fPIC", "-shared"]
COMPILE_TIMEOUT = 600
SOURCE_NAME = "dyad_dae.c"
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
    same rows in the same order), for the root finding of the native IDAS driver (compiler/native),
    which calls it from C; `atol` is an input because the bounds' slack depends on the run's
    absolute tolerance. None of it for a model that watches nothing."""
    x, z, p, t = symbols = model.symbols()
    atol = ca.SX.sym("atol")
    rows, labels = watches.watched_rows(model, symbols, atol)
    return [ca.Function("dyad_watch", [x, z, p, t, atol], [rows])] if labels else []


def c_source(model: CompiledModel) -> str:
    dae = dae_function(model)
    with tempfile.TemporaryDirectory(prefix="dyadc-cg-") as tmp:
        generator = ca.CodeGenerator(Path(SOURCE_NAME).stem, {"with_header": False})
        generator.add(dae)
        generator.add(state_jacobian(dae))
        for function in pointwise_functions(model) + watch_functions(model):
            generator.add(function)
        generator.generate(tmp + os.sep)        # the prefix is the output directory
        return (Path(tmp) / SOURCE_NAME).read_text(encoding="utf-8")


def find_compiler() -> str | None:
    configured = os.environ.get("CC")
    for candidate in ([configured] if configured else []) + ["gcc", "cc", "clang"]:
        found = shutil.which(candidate)
        if found:
            return found
    return None


def compiler_identity(compiler: str) -> str:
    """The first line of `compiler --version` (what a library built by it depends on)."""
    try:
        done = subprocess.run([compiler, "--version"], capture_output=True, text=True, timeout=30)
        return done.stdout.splitlines()[0] if done.stdout else compiler
    except (OSError, subprocess.SubprocessError):
        return compiler


def compile_library(source: str, compiler: str, folder: Path) -> Path:
    """Compile `source` into a shared library inside `folder` (relative names only: the library's
    bytes do not depend on where it was built, so two processes that race to build one library
    make identical files)."""
    (folder / SOURCE_NAME).write_text(source, encoding="utf-8")
    built = "dyad_dae.so"
    done = subprocess.run([compiler, *FLAGS, SOURCE_NAME, "-o", built, "-lm"], cwd=folder,
                          capture_output=True, text=True, timeout=COMPILE_TIMEOUT)
    if done.returncode != 0:
        raise RuntimeError(f"{Path(compiler).name} failed: {done.stderr.strip()[-2000:]}")
    return folder / built
