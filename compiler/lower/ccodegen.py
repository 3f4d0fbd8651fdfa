"""`--codegen c`: compile the DAE residual, its Jacobian and the per-point functions to a shared library.

CasADi's CodeGenerator writes C for `dyad_dae(t, x, z, p, u) -> (ode, alg, quad, zero)` plus its
Jacobian function `jac_dyad_dae`; `casadi.external` then finds the Jacobian in the same library by
name, which is all IDAS needs (measured with CasADi 3.8: adding forward/reverse derivative functions
instead makes IDAS 10-200x slower, and the integrator's own 'jit' option recompiles on every
construction and took 11 s for a 600-unknown model).

The same library holds the functions of (x, z, p, t) the runtime evaluates at every output point
(`pointwise_functions`: the outputs and the polishing's Newton step on the algebraic equations), which
compiler/runtime/outputs.py and polishing.py otherwise run on the VM. Excavator at -O1 (CPU):
outputs and polishing at 1201 points 7.4 + 9.8-14.7 ms -> 1.9 + 2.7 ms, bit-identical; the build
grows from 0.76 s and 112 kB to 1.17 s and 183 kB (the whole library at -O0: 0.44 s, but outputs
and polishing then take 4.4 + 4.7 ms, most of the gain gone; -O2 runs no faster). With the
outputs at z polished by a one-function Newton step (compiler/runtime/polishing.py) in place of
the outputs, the Newton function and the residual, for up to 4 algebraic unknowns: its
evaluations over a run's 1201 points 2.7 ms (the step and the outputs apart: 3.5 ms), the build
1.19-1.25 s and 162 kB (1.32-1.42 s and 183 kB before, in the same runs).

`jac_dyad_dae` differentiates with respect to x and z only: its t and p blocks are structurally
zero. IDAS (and its consistent-initial-condition step) uses only d(ode, alg)/d(x, z); the t and
p blocks were a third of the C source and half the build time (excavator at -O1: 222 kB, 1.3-1.5 s
-> 157 kB, 0.7-0.8 s, run time unchanged). So this Jacobian is for the integrator only: anything
that needs derivatives in t or p (sensitivities) must use the model's CasADi functions instead.

Flags: -O1 (excavator: -O0 builds in 0.3-0.6 s but runs 20-35 % slower; -O2 builds 10-40 % longer
than -O1 and runs no faster). Libraries are cached by a hash of their C source, the compiler and
its flags (compiler/lower/c_cache.py: validated, rebuilt when damaged). Names of the model never reach
the C code: every identifier in it is a fixed one of ours (dyad_dae, x, z, p, t). Without a C
compiler the model stays on CasADi's SX virtual machine, with a warning.
"""
from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import tempfile
import warnings
from pathlib import Path

import casadi as ca

from compiler.lower import c_cache
from compiler.runtime import CompiledModel, polishing

FLAGS = ["-O1", "-fPIC", "-shared"]
COMPILE_TIMEOUT = 600
_SOURCE_NAME = "dyad_dae.c"
_DIFFERENTIATED_INPUTS = ("x", "z")


class CodegenWarning(UserWarning):
    pass


def cache_dir() -> Path:
    return c_cache.cache_dir()


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


def c_source(model: CompiledModel) -> str:
    dae = dae_function(model)
    with tempfile.TemporaryDirectory(prefix="dyadc-cg-") as tmp:
        generator = ca.CodeGenerator(Path(_SOURCE_NAME).stem, {"with_header": False})
        generator.add(dae)
        generator.add(state_jacobian(dae))
        for function in pointwise_functions(model):
            generator.add(function)
        generator.generate(tmp + os.sep)        # the prefix is the output directory
        return (Path(tmp) / _SOURCE_NAME).read_text(encoding="utf-8")


def find_compiler() -> str | None:
    configured = os.environ.get("CC")
    for candidate in ([configured] if configured else []) + ["gcc", "cc", "clang"]:
        found = shutil.which(candidate)
        if found:
            return found
    return None


def _compiler_identity(compiler: str) -> str:
    try:
        done = subprocess.run([compiler, "--version"], capture_output=True, text=True, timeout=30)
        return done.stdout.splitlines()[0] if done.stdout else compiler
    except (OSError, subprocess.SubprocessError):
        return compiler


def cache_key(source: str, compiler: str) -> str:
    parts = [source, _compiler_identity(compiler), " ".join(FLAGS), ca.__version__,
             f"entry format {c_cache.ENTRY_FORMAT}"]
    return hashlib.sha256("\0".join(parts).encode()).hexdigest()[:32]


def build_library(source: str, compiler: str, directory: Path | None = None) -> Path:
    """Compile `source` to a shared library, or return the cached one built from identical input."""
    return _fetch_or_build(source, compiler, Path(directory or cache_dir()))[0]


def _fetch_or_build(source: str, compiler: str, directory: Path) -> tuple[Path, bool, str]:
    key = cache_key(source, compiler)

    def build(scratch: Path) -> Path:
        # Relative names inside the scratch folder: the library's bytes do not depend on where
        # it was built, so two processes that race to build one entry make identical files.
        (scratch / _SOURCE_NAME).write_text(source, encoding="utf-8")
        built = "dyad_dae.so"
        done = subprocess.run([compiler, *FLAGS, _SOURCE_NAME, "-o", built, "-lm"], cwd=scratch,
                              capture_output=True, text=True, timeout=COMPILE_TIMEOUT)
        if done.returncode != 0:
            raise RuntimeError(f"{Path(compiler).name} failed: {done.stderr.strip()[-2000:]}")
        return scratch / built

    library, built_now = c_cache.fetch_or_build(directory, key, build)
    return library, built_now, key


def compile_c(model: CompiledModel, directory: Path | None = None) -> CompiledModel:
    """A copy of `model` that evaluates its DAE through a compiled C library (the input is left as
    it was); a copy on the VM, with a warning, where C is unavailable."""
    compiler = find_compiler()
    if compiler is None:
        return _fallback(model, "no C compiler (gcc, cc or clang) found")
    directory = Path(directory or cache_dir())
    try:
        source = c_source(model)
        library, built_now, key = _fetch_or_build(source, compiler, directory)
        try:
            native = _load(model, library)
        except (RuntimeError, ValueError):
            if built_now:
                raise
            # Checksums match what was written, yet it does not load (say, a library from a
            # different machine sharing the folder): forget the entry and build it once more.
            c_cache.discard(directory, key)
            library = _fetch_or_build(source, compiler, directory)[0]
            native = _load(model, library)
    except (RuntimeError, OSError, subprocess.SubprocessError, ValueError) as err:
        return _fallback(model, str(err))
    return native.replace(metadata={**model.metadata, "codegen": "c"},
                          variants={k: compile_c(v, directory) for k, v in model.variants.items()})


def _load(model: CompiledModel, library: Path) -> CompiledModel:
    native = model.with_native_library(library)
    native.native_dae()                 # load now: a broken library is a fallback, not a crash
    return native


def _fallback(model: CompiledModel, why: str) -> CompiledModel:
    warnings.warn(f"C code generation unavailable ({why}); using the CasADi virtual machine",
                  CodegenWarning, stacklevel=3)
    return model.replace(native_library=None, metadata={**model.metadata, "codegen": "vm"})


def use_c_code(model: CompiledModel) -> CompiledModel:
    """The CLI's `--codegen c`: `model` with its DAE compiled to C (or unchanged, with a warning)."""
    return compile_c(model)
