"""A model on C code (`--codegen c`): its shared library from the C library cache, or built into
it (compiler/lower/ccodegen.py writes and compiles the C; c_libraries.py keeps validated entries).

A library is keyed by its C source, the C compiler's identity, the flags and CasADi's version, so
identical input is built once. Without a C compiler, or when the build fails, the model stays on
CasADi's SX virtual machine, with a CodegenWarning.
"""
from __future__ import annotations

import hashlib
import subprocess
import warnings
from pathlib import Path

import casadi as ca

from compiler.cache import c_libraries
from compiler.lower import ccodegen
from compiler.runtime import CompiledModel


def cache_key(source: str, compiler: str) -> str:
    parts = [source, ccodegen.compiler_identity(compiler), " ".join(ccodegen.FLAGS), ca.__version__,
             f"entry format {c_libraries.ENTRY_FORMAT}"]
    return hashlib.sha256("\0".join(parts).encode()).hexdigest()[:32]


def build_library(source: str, compiler: str, directory: Path | None = None) -> Path:
    """Compile `source` to a shared library, or return the cached one built from identical input."""
    return _fetch_or_build(source, compiler, Path(directory or c_libraries.cache_dir()))[0]


def _fetch_or_build(source: str, compiler: str, directory: Path) -> tuple[Path, bool, str]:
    key = cache_key(source, compiler)
    library, built_now = c_libraries.fetch_or_build(
        directory, key, lambda scratch: ccodegen.compile_library(source, compiler, scratch))
    return library, built_now, key


def compile_c(model: CompiledModel, directory: Path | None = None) -> CompiledModel:
    """A copy of `model` that evaluates its DAE through a compiled C library (the input is left as
    it was), kept in `directory` (default: the C library cache); a copy on the VM, with a warning,
    where C is unavailable."""
    compiler = ccodegen.find_compiler()
    if compiler is None:
        return _fallback(model, "no C compiler (gcc, cc or clang) found")
    directory = Path(directory or c_libraries.cache_dir())
    try:
        source = ccodegen.c_source(model)
        library, built_now, key = _fetch_or_build(source, compiler, directory)
        try:
            native = _load(model, library)
        except (RuntimeError, ValueError):
            if built_now:
                raise
            # Checksums match what was written, yet it does not load (say, a library from a
            # different machine sharing the folder): forget the entry and build it once more.
            c_libraries.discard(directory, key)
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
                  ccodegen.CodegenWarning, stacklevel=3)
    return model.replace(native_library=None, metadata={**model.metadata, "codegen": "vm"})
