"""What a compiled model depends on, as hashes.

A compile depends on (1) the request: the model spec, the library search path (shipped library,
-L folders, DYADC_PATH) and the compile options; (2) the compiler: its version, the bytes of its
own package (so an edited checkout never reuses a stale model), CasADi's and Python's versions;
(3) the sources it read. The first two give the *lookup key*, known before anything is read. The
third is only known after a compile, which records it as a list of *inputs*:

  ("file", path)      the SHA-256 of a .dyad file the library read (parsed or only scanned);
  ("folder", path)    the sorted .dyad and subfolder names in a folder the library searched for a
                      name (a file added there could now define it, a subpackage added there
                      could make a flat path an alias or ambiguous), or "absent";
  ("plugin", path)    the SHA-256 of a dyad_functions.py the library looked for, or "absent";
  ("julia", path)     the names and SHA-256s of the Julia sources of a package folder it read.

The *entry key* hashes the lookup key with every input and its fingerprint: the hash of all
sources used. A later run recomputes the fingerprints of the recorded inputs; if all match, the
entry key is the same and the compiled model is reused. Imports the standard library and casadi.
"""
from __future__ import annotations

import hashlib
import json
import os
import sys
from functools import lru_cache
from pathlib import Path
from typing import Iterable, Sequence

from compiler.julia.functions import julia_source_files

KEY_FORMAT = 1
ABSENT = "absent"
_COMPILER_FILES = (".py", ".lark", ".json")
_SKIPPED_FOLDERS = ("__pycache__", "components")    # the shipped library is hashed as sources

Input = tuple[str, str]        # (kind, absolute path)


def hash_text(*parts: str) -> str:
    return hashlib.sha256("\0".join(parts).encode("utf-8", "surrogatepass")).hexdigest()


@lru_cache(maxsize=None)
def compiler_fingerprint() -> str:
    """The compiler's version, a hash of every file of its package, CasADi's and Python's
    versions (computed once per process)."""
    import casadi            # imported by every run anyway; importlib.metadata would cost 20 ms
    import compiler
    package = Path(compiler.__file__).resolve().parent
    digest = hashlib.sha256()
    for folder, subfolders, files in os.walk(package):
        subfolders[:] = sorted(d for d in subfolders if d not in _SKIPPED_FOLDERS)
        for name in sorted(files):
            if name.endswith(_COMPILER_FILES):
                path = Path(folder, name)
                digest.update(str(path.relative_to(package)).encode() + b"\0")
                digest.update(path.read_bytes() + b"\0")
    return hash_text(f"dyadc {compiler.__version__}", digest.hexdigest(), f"casadi {casadi.__version__}",
                      f"python {sys.version_info[0]}.{sys.version_info[1]}", f"keys {KEY_FORMAT}")


def normalized_spec(spec: str) -> str:
    """A model spec with its file part made absolute: `cd a; dyadc simulate M.dyad` and
    `cd b; dyadc simulate M.dyad` are different models."""
    file_part, colon, name = spec.partition(":") if ".dyad:" in spec else (spec, "", "")
    if file_part.endswith(".dyad"):
        return os.path.abspath(file_part) + colon + name
    return spec


def lookup_key(spec: str, roots: Sequence[tuple[str, str, bool]], options: dict) -> str:
    """The request and the compiler: `roots` are the search path's (path, origin, runs code)."""
    request = json.dumps({"spec": normalized_spec(spec), "roots": [list(r) for r in roots],
                          "options": options}, sort_keys=True)
    return hash_text("lookup", compiler_fingerprint(), request)


def entry_key(lookup: str, fingerprints: Iterable[tuple[str, str, str]]) -> str:
    """The hash of the request, the compiler and every (kind, path, fingerprint) input."""
    return hash_text("entry", lookup, json.dumps(sorted(list(f) for f in fingerprints)))


def fingerprint(kind: str, path: str) -> str:
    """The current fingerprint of one input (see the module's docstring)."""
    target = Path(path)
    try:
        if kind == "folder":
            if not target.is_dir():
                return ABSENT
            return hash_text(*sorted(p.name + ("/" if p.is_dir() else "") for p in target.iterdir()
                                     if p.name.endswith(".dyad") or p.is_dir()))
        if kind == "julia":
            return _julia_fingerprint(target)
        if kind in ("file", "plugin"):
            if not target.is_file():
                return ABSENT
            return hashlib.sha256(target.read_bytes()).hexdigest()
    except OSError:
        return ABSENT
    raise ValueError(f"unknown cache input kind {kind!r}")


def _julia_fingerprint(package_folder: Path) -> str:
    """The names and bytes of the Julia sources of a package folder (found by the rule of
    compiler.julia.functions.julia_source_files)."""
    files = julia_source_files(package_folder)
    if not files:
        return ABSENT
    return hash_text(*(f"{p.name}:{hashlib.sha256(p.read_bytes()).hexdigest()}" for p in files))
