"""`--codegen c`: compile the DAE residual and its Jacobian to a shared library.

CasADi's CodeGenerator writes C for `dyad_dae(t, x, z, p, u) -> (ode, alg, quad, zero)` plus its
Jacobian function `jac_dyad_dae`; `casadi.external` then finds the Jacobian in the same library by
name, which is all IDAS needs (measured with CasADi 3.8: adding forward/reverse derivative functions
instead makes IDAS 10-200x slower, and the integrator's own 'jit' option recompiles on every
construction and took 11 s for a 600-unknown model). Libraries are cached by a hash of their C
source, the compiler and its flags under $DYADC_CACHE or ~/.cache/dyadc. Without a C compiler the
model stays on CasADi's SX virtual machine, with a warning.
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

from compiler.runtime import CompiledModel

FLAGS = ["-O2", "-fPIC", "-shared"]
COMPILE_TIMEOUT = 600


class CodegenWarning(UserWarning):
    pass


def cache_dir() -> Path:
    configured = os.environ.get("DYADC_CACHE")
    return Path(configured) if configured else Path.home() / ".cache" / "dyadc"


def dae_function(model: CompiledModel) -> ca.Function:
    """The model's DAE with the signature CasADi integrators take (t, x, z, p, u)."""
    nx, nz, npar = len(model.state_names), len(model.algebraic_names), len(model.parameter_names)
    x, z, p, t, u = (ca.SX.sym("x", nx), ca.SX.sym("z", nz), ca.SX.sym("p", npar), ca.SX.sym("t"),
                     ca.SX.sym("u", 0))
    ode, alg = model.dae(x, z, p, t)
    return ca.Function(CompiledModel.NATIVE_DAE_NAME, [t, x, z, p, u],
                       [ode, alg, ca.SX(0, 1), ca.SX(0, 1)], ca.dyn_in(), ca.dyn_out())


def c_source(model: CompiledModel) -> str:
    dae = dae_function(model)
    with tempfile.TemporaryDirectory(prefix="dyadc-cg-") as tmp:
        generator = ca.CodeGenerator("dyad_dae", {"with_header": False})
        generator.add(dae)
        generator.add(dae.jacobian())
        generator.generate(tmp + os.sep)        # the prefix is the output directory
        return (Path(tmp) / "dyad_dae.c").read_text(encoding="utf-8")


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


def build_library(source: str, compiler: str, directory: Path | None = None) -> Path:
    """Compile `source` to a shared library, or return the cached one built from identical input."""
    directory = directory or cache_dir()
    key = hashlib.sha256("\0".join([source, _compiler_identity(compiler), " ".join(FLAGS),
                                    ca.__version__]).encode()).hexdigest()[:32]
    library = directory / f"dyad_{key}.so"
    if library.exists():
        return library
    directory.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="dyadc-cc-", dir=directory) as tmp:
        c_file = Path(tmp) / "dyad_dae.c"
        c_file.write_text(source, encoding="utf-8")
        built = Path(tmp) / library.name
        done = subprocess.run([compiler, *FLAGS, str(c_file), "-o", str(built), "-lm"],
                              capture_output=True, text=True, timeout=COMPILE_TIMEOUT)
        if done.returncode != 0:
            raise RuntimeError(f"{Path(compiler).name} failed: {done.stderr.strip()[-2000:]}")
        os.replace(built, library)          # atomic: concurrent builders all end with one file
    return library


def compile_c(model: CompiledModel, directory: Path | None = None) -> CompiledModel:
    """Attach a compiled DAE library to `model` (same object returned); fall back to the VM."""
    compiler = find_compiler()
    if compiler is None:
        return _fallback(model, "no C compiler (gcc, cc or clang) found")
    try:
        library = build_library(c_source(model), compiler, directory)
        model.use_native_library(library)
        model.native_dae()                  # load now: a broken library is a fallback, not a crash
    except (RuntimeError, OSError, subprocess.SubprocessError, ValueError) as err:
        model.use_native_library(None)
        return _fallback(model, str(err))
    model.metadata["codegen"] = "c"
    return model


def _fallback(model: CompiledModel, why: str) -> CompiledModel:
    warnings.warn(f"C code generation unavailable ({why}); using the CasADi virtual machine",
                  CodegenWarning, stacklevel=3)
    model.metadata["codegen"] = "vm"
    return model


def use_c_code(model: CompiledModel) -> CompiledModel:
    """The CLI's `--codegen c`: `model` with its DAE compiled to C (or unchanged, with a warning)."""
    return compile_c(model)
