"""`dyadc simulate --codegen c` with the cache: the C library of a cached model is used when the
cache has it; otherwise it is built by a second process while this one already runs the model on
CasADi's virtual machine, and the next run uses it.

The builder (a Python process running `build(ENTRY_KEY)`) reads the compiled model from the
cache entry, generates and compiles its C code (c_code.py: the validated C library cache of
c_libraries.py, one build per library even when several processes ask) and writes
a *link* `models/<entry key>.c-<hash of compiler and flags>.link` naming the library's key, so
that a later run finds the library without generating C again. The run that started it waits
for it before exiting (a few tenths of a second after a short run): the next run finds the
library, and no process is left behind.
"""
from __future__ import annotations

import atexit
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import compiler
from compiler.cache import c_libraries, keys
from compiler.cache.c_code import compile_c
from compiler.cache.models import models_folder, read_entry
from compiler.cache.store import read_sealed, write_sealed

LINK_SUFFIX = ".link"
_KEY = re.compile(r"[0-9a-f]{16,64}")


def _link_path(folder: Path, entry_key: str, compiler: str) -> Path:
    from compiler.lower.ccodegen import FLAGS
    tag = keys.hash_text(compiler, " ".join(FLAGS))[:16]
    return folder / f"{entry_key}.c-{tag}{LINK_SUFFIX}"


def cached_library(entry_key: str, compiler: str) -> Path | None:
    """The valid cached C library of entry `entry_key`, if one was built."""
    folder = models_folder()
    if folder is None:
        return None
    payload = read_sealed(_link_path(folder, entry_key, compiler))
    key = payload.decode("ascii", "replace").strip() if payload is not None else ""
    if not _KEY.fullmatch(key):               # a key names a file: hexadecimal digits only
        return None
    return c_libraries.valid_entry(c_libraries.cache_dir(), key)


class BackgroundBuild:
    """A builder process started for one entry; `finish()` waits for it and says how it went."""

    def __init__(self, entry_key: str):
        self.began = time.perf_counter()
        # the builder imports the same compiler package as this process, whatever its folder
        home = str(Path(compiler.__file__).resolve().parent.parent)
        code = (f"import sys; sys.path.insert(0, {home!r}); from compiler.cache.native import build; "
                f"raise SystemExit(build({entry_key!r}))")
        self.process = subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.DEVNULL,
                                        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)

    def finish(self) -> str:
        """Wait for the builder; the line to show the user."""
        _, errors = self.process.communicate()
        seconds = time.perf_counter() - self.began
        if self.process.returncode == 0:
            return (f"built the model's C library in the background ({seconds:.1f} s); the next run "
                    f"with --codegen c uses it")
        lines = (errors or "").strip().splitlines()
        if lines and "unavailable" in lines[-1]:
            return f"warning: {lines[-1]}"
        why = lines[-1] if lines else f"the builder stopped with exit status {self.process.returncode}"
        return f"warning: C code generation unavailable ({why}); this run used the CasADi virtual machine"


def use_c_code(compilation, cache: bool = True) -> BackgroundBuild | None:
    """Put `compilation` on C code: the cached library at once, else (from the cache) a build in
    the background while this run uses the virtual machine. Without the cache (`cache=False`) the
    library is built now in a temporary folder; for a model the cache does not hold, or one with
    several state sets (each needs its library), it is built now into the C cache."""
    from compiler.lower import ccodegen
    compiler = ccodegen.find_compiler()
    key = getattr(compilation, "cache_key", None)
    if not cache:             # nothing read or kept: a library in a folder removed at exit
        scratch = Path(tempfile.mkdtemp(prefix="dyadc-c-"))
        atexit.register(shutil.rmtree, scratch, True)
        compilation.model = compile_c(compilation.model, scratch)
        return None
    if key is None or compiler is None or models_folder() is None or getattr(compilation.model, "variants", None):
        compilation.model = compile_c(compilation.model)      # (every state set in C)
        return None
    library = cached_library(key, compiler)
    if library is not None:
        native = compilation.model.with_native_library(library)
        try:
            native.native_dae()                # a library that does not load is rebuilt
        except (RuntimeError, ValueError):
            c_libraries.discard(c_libraries.cache_dir(), library.stem.removeprefix("dyad_"))
        else:
            compilation.model = native.replace(metadata={**native.metadata, "codegen": "c"})
            return None
    return BackgroundBuild(key)


def build(entry_key: str) -> str | None:
    """The builder process: compile the C library of entry `entry_key` and link it. None when it
    did; else why not (the process exits with it, on its standard error, which
    BackgroundBuild.finish reads)."""
    import warnings
    from compiler.lower import ccodegen
    found = read_entry(entry_key)
    compiler = ccodegen.find_compiler()
    folder = models_folder()
    if found is None or compiler is None or folder is None:
        return "the cache entry or the C compiler is gone"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", ccodegen.CodegenWarning)
        native = compile_c(found[0])
    if native.native_library is None:
        return next((str(w.message) for w in caught if issubclass(w.category, ccodegen.CodegenWarning)),
                    "no library")
    library = Path(native.native_library)
    write_sealed(_link_path(folder, entry_key, compiler), library.stem.removeprefix("dyad_").encode("ascii"))
    return None
