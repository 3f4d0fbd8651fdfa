"""A model on C code: its shared libraries (the model's and each state set's) from the C library
cache, or built into it (compiler/lower/ccodegen.py writes and compiles the C; c_libraries.py keeps
validated entries).

A library is keyed by its C source, the C compiler's identity, the flags and CasADi's version, so
identical input is built once, whichever process or model asks. `start_c_build` writes the C and
starts the compilers (threads waiting on compiler processes) and returns at once, so the caller
can go on (store the compiled model) while they run; `CBuild.finish` waits and gives the model on C.
Without a C compiler, or when a build fails, the model stays on CasADi's SX virtual machine, with a
CodegenWarning; with a C compiler a model runs on C, never on a mix (all its libraries or none).
`start` makes the choice (C or the VM) and begins the build; `for_a_run` is the same for a model
that reaches the runtime undecided (compiler/runtime/model_code.py), and imports no more of the
compiler than this module does, so a generated module's first run stays light.
"""
from __future__ import annotations

import concurrent.futures
import hashlib
import os
import subprocess
import time
import warnings
from pathlib import Path

import casadi as ca

from compiler.cache import c_libraries
from compiler.cache.codegen_choice import record_choice, requested
from compiler.lower import ccodegen
from compiler.runtime import CompiledModel

_BUILD_ERRORS = (RuntimeError, OSError, subprocess.SubprocessError, ValueError)


def cache_key(source: str | dict[str, str], compiler: str) -> str:
    """The content key of a library built from `source` (one C file, or {file name: source})."""
    units = source if isinstance(source, dict) else {ccodegen.SOURCE_NAME: source}
    parts = [part for name, text in sorted(units.items()) for part in (name, text)]
    parts += [ccodegen.compiler_identity(compiler), " ".join(ccodegen.COMPILE_FLAGS),
              " ".join(ccodegen.LINK_FLAGS), ca.__version__, f"entry format {c_libraries.ENTRY_FORMAT}"]
    return hashlib.sha256("\0".join(parts).encode()).hexdigest()[:32]


def build_library(source: str, compiler: str, directory: Path | None = None) -> Path:
    """Compile `source` to a shared library, or return the cached one built from identical input."""
    directory = Path(directory or c_libraries.cache_dir())
    return c_libraries.fetch_or_build(directory, cache_key(source, compiler),
                                      lambda scratch: ccodegen.compile_library(source, compiler, scratch))[0]


class CBuild:
    """The C libraries of one model (and of each of its state sets) on their way: started by
    `start_c_build`, waited for by `finish`."""

    def __init__(self, model: CompiledModel, directory: Path, compiler: str | None,
                 problem: str | None = None):
        self.model, self.directory, self.compiler = model, directory, compiler
        self.problem = problem                 # why there is no build (no compiler, no C source)
        self.keys: dict[frozenset | None, str] = {}
        self.pending: dict[frozenset | None, concurrent.futures.Future] = {}
        self._pool: concurrent.futures.ThreadPoolExecutor | None = None

    def start(self) -> "CBuild":
        """Each part's C written, and its build started at once (while the next part's C is written)."""
        parts = {None: self.model, **self.model.variants}
        # a build per core at a time (each runs one or two compiler processes of ~100 MB)
        self._pool = concurrent.futures.ThreadPoolExecutor(max_workers=min(len(parts), os.cpu_count() or 1),
                                                           thread_name_prefix="dyadc-cc")
        try:
            for which, part in parts.items():
                sources = ccodegen.c_units(part)
                self.keys[which] = cache_key(sources, self.compiler)
                self.pending[which] = self._pool.submit(self._fetch_or_build, self.keys[which], sources)
        except (RuntimeError, ValueError) as err:       # CasADi cannot write C for a function
            self.problem = f"no C code for {self.model.name}: {err}"
        self._pool.shutdown(wait=False)
        return self

    def _fetch_or_build(self, key: str, sources: dict[str, str]) -> Path:
        return c_libraries.fetch_or_build(
            self.directory, key, lambda scratch: ccodegen.compile_units(sources, self.compiler, scratch))[0]

    def finish(self) -> CompiledModel:
        """The model on C (every state set's library loaded), or on the VM with a CodegenWarning."""
        if self.problem is not None:
            return fallback(self.model, self.problem)
        try:
            libraries = {which: future.result() for which, future in self.pending.items()}
            native = {which: self._loaded(which, library) for which, library in libraries.items()}
        except _BUILD_ERRORS as err:
            return fallback(self.model, str(err))
        main = native.pop(None)
        return record_choice(main.replace(variants={k: record_choice(v, "c") for k, v in native.items()}), "c")

    def _loaded(self, which: frozenset | None, library: Path) -> CompiledModel:
        part = self.model if which is None else self.model.variants[which]
        try:
            return _load(part, library)
        except (RuntimeError, ValueError):
            # Checksums match what was written, yet it does not load (say, a library from another
            # machine sharing the folder): forget the entry and build it once more.
            c_libraries.discard(self.directory, self.keys[which])
            return _load(part, self._fetch_or_build(self.keys[which], ccodegen.c_units(part)))


def start_c_build(model: CompiledModel, directory: Path | None = None) -> CBuild:
    """Write the C code of `model` and start building its libraries in `directory` (default: the C
    library cache); returns at once."""
    compiler = ccodegen.find_compiler()
    directory = Path(directory or c_libraries.cache_dir())
    if compiler is None:
        return CBuild(model, directory, None, "no C compiler (gcc, cc or clang) found")
    return CBuild(model, directory, compiler).start()


def compile_c(model: CompiledModel, directory: Path | None = None) -> CompiledModel:
    """A copy of `model` that evaluates its functions through compiled C libraries (the input is
    left as it was), kept in `directory` (default: the C library cache); a copy on the VM, with a
    warning, where C is unavailable."""
    return start_c_build(model, directory).finish()


def with_library(model: CompiledModel, library: Path) -> CompiledModel | None:
    """`model` on the C library `library` (loaded now), or None when it does not load."""
    try:
        return record_choice(_load(model, library), "c")
    except (RuntimeError, ValueError):
        return None


def _load(model: CompiledModel, library: Path) -> CompiledModel:
    native = model.with_native_library(library)
    native.native_dae()                 # load now: a broken library is a fallback, not a crash
    return native


def fallback(model: CompiledModel, why: str) -> CompiledModel:
    """`model` on the VM because C failed: with a CodegenWarning saying why."""
    warnings.warn(f"C code generation unavailable ({why}); using the CasADi virtual machine",
                  ccodegen.CodegenWarning, stacklevel=3)
    return on_vm(model, why)


def on_vm(model: CompiledModel, why: str | None = None) -> CompiledModel:
    """`model` (and each state set) on CasADi's virtual machine; `why` when it was not asked for."""
    return record_choice(model.replace(native_library=None, variants={
        k: record_choice(v.replace(native_library=None), "vm") for k, v in model.variants.items()}), "vm", why)


# -- a model put on its code before its first run --------------------------------------------------

class Started:
    """A model's code on its way: `finish()` gives the model on it (C, or the VM)."""

    def __init__(self, model, build: CBuild | None, why_vm: str | None):
        self.model, self.build, self.why_vm = model, build, why_vm
        self.seconds = 0.0                   # the wall time spent starting and waiting

    def finish(self):
        began = time.perf_counter()
        model = on_vm(self.model, self.why_vm) if self.build is None else self.build.finish()
        self.seconds += time.perf_counter() - began
        return model


def start(model, codegen: str | None = None, directory: Path | None = None) -> Started:
    """Begin putting `model` on its code: `codegen` "c", "vm" or None (C where a compiler is
    present; $DYADC_CODEGEN may say otherwise); libraries in `directory` (default: the C cache)."""
    began = time.perf_counter()
    choice = requested(codegen)
    if choice == "vm":
        started = Started(model, None, None)
    elif choice is None and ccodegen.find_compiler() is None:
        started = Started(model, None, "no C compiler (gcc, cc or clang) found")
    else:
        started = Started(model, start_c_build(model, directory), None)
    started.seconds = time.perf_counter() - began
    return started


def for_a_run(model):
    """The build the runtime calls for a model that reaches a run with its code unsettled (a
    generated module's, one read back with from_dict, one lowered without C; entry point
    `dyadc.model_code`, compiler/runtime/model_code.py): `start`'s choice and build, the ones
    `dyadc simulate` makes, so both run on the same library."""
    return start(model).finish()
