"""A compiled model put on its code before its first run (codegen_choice.py): on C where a C
compiler is present, built before the run (c_code.py), so every run of a model takes the same path
and no number depends on whether a build had finished.

`start` (c_code.py) begins the build as soon as the model is lowered; the caller stores the compiled model
meanwhile and `Started.finish` waits for it. A model from the compilation cache finds its
libraries through a *link* `models/<entry key>.c-<hash of compiler and flags>.link` naming the key
of each library (the model's and each state set's), so that a cached run neither writes C nor
waits for a compiler; a missing or damaged link, or a library that no longer matches its record,
means the libraries are built again (content keyed: the same input gives the same library).
"""
from __future__ import annotations

import atexit
import json
import re
import shutil
import tempfile
from pathlib import Path

from compiler.cache import c_libraries, keys
from compiler.cache.c_code import CBuild, Started, start, with_library  # noqa: F401  (start: native.start)
from compiler.cache.codegen_choice import chosen, requested
from compiler.cache.models import models_folder
from compiler.cache.store import read_sealed, write_sealed

LINK_SUFFIX = ".link"
_KEY = re.compile(r"[0-9a-f]{16,64}")


def on_its_code(model, codegen: str | None = None):
    """`model` on its code, built now if need be; a model whose code was chosen stays as it is."""
    return model if chosen(model) is not None else start(model, codegen).finish()


def temporary_folder() -> Path:
    """A folder for libraries that nothing keeps (`--no-cache`), removed when the process ends."""
    scratch = Path(tempfile.mkdtemp(prefix="dyadc-c-"))
    atexit.register(shutil.rmtree, scratch, True)
    return scratch


# -- links from cached models to their libraries ------------------------------------------------

def _link_path(folder: Path, entry_key: str, compiler: str) -> Path:
    from compiler.lower.ccodegen import FLAGS
    tag = keys.hash_text(compiler, " ".join(FLAGS))[:16]
    return folder / f"{entry_key}.c-{tag}{LINK_SUFFIX}"


def _part_name(which: frozenset | None) -> str:
    return "" if which is None else ",".join(sorted(which))


def linked_model(model, entry_key: str, compiler: str):
    """The cached `model` on the libraries its link names, or None (no link, a damaged one, or a
    library that is gone, changed or does not load)."""
    folder = models_folder()
    payload = read_sealed(_link_path(folder, entry_key, compiler)) if folder is not None else None
    try:
        named = json.loads(payload) if payload is not None else None
    except ValueError:
        return None
    parts = {_part_name(None): model, **{_part_name(k): v for k, v in model.variants.items()}}
    if not isinstance(named, dict) or set(named) != set(parts) or \
            not all(isinstance(key, str) and _KEY.fullmatch(key) for key in named.values()):
        return None                            # a key names a file: hexadecimal digits only
    native = {}
    for name, part in parts.items():
        library = c_libraries.valid_entry(c_libraries.cache_dir(), named[name])
        native[name] = with_library(part, library) if library is not None else None
        if native[name] is None:
            return None
    main = native.pop("")
    return main.replace(variants={k: native[_part_name(k)] for k in model.variants})


def write_link(entry_key: str, build: CBuild) -> None:
    """Record which libraries the cached model `entry_key` runs on."""
    folder = models_folder()
    if folder is None or build.compiler is None or len(build.keys) != 1 + len(build.model.variants):
        return
    named = {_part_name(which): key for which, key in build.keys.items()}
    write_sealed(_link_path(folder, entry_key, build.compiler),
                 json.dumps(named, sort_keys=True).encode("ascii"))


def cached_on_its_code(model, entry_key: str, codegen: str | None = None):
    """A cached model on its code: on C through its link when it has one, else built now (and
    linked for the next run)."""
    from compiler.lower import ccodegen
    compiler = ccodegen.find_compiler()
    if requested(codegen) != "vm" and compiler is not None:
        linked = linked_model(model, entry_key, compiler)
        if linked is not None:
            return linked
    started = start(model, codegen)
    native = started.finish()
    if chosen(native) == "c":
        write_link(entry_key, started.build)
    return native
