"""Compiled models in the cache: `<root>/models/<lookup key>.manifest` lists the inputs a compile
read with their fingerprints and names the entry `<root>/models/<entry key>.model`, which holds
the serialized CompiledModel (CompiledModel.to_dict, as sweeps ship it to workers) and what a run
needs from the sources besides: the parameters that must be given a value, and where variables
are declared (to locate a failure). Both files are sealed (store.py): a damaged one is a miss.

Loading imports the runtime (casadi, numpy) and this package only: no sympy, no lark.
"""
from __future__ import annotations

import dataclasses
import json
import logging
import os
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence

from compiler.cache import keys
from compiler.cache.store import cache_root, private_folder, read_sealed, write_sealed
from compiler.errors import Span
from compiler.runtime import CompiledModel

ENTRY_FORMAT = 1
MODELS_FOLDER = "models"
MANIFEST_SUFFIX = ".manifest"
ENTRY_SUFFIX = ".model"
# The models folder is kept under this size: after a store, the least recently used files go
# first (a hit touches its entry) until it is under three quarters of it.
MAX_FOLDER_BYTES = 512 * 1024 * 1024
STALE_TEMPORARY_SECONDS = 3600        # a writer's temporary file older than this was left by a killed run
logger = logging.getLogger(__name__)


@dataclass
class CachedCompilation:
    """A compilation read from the cache: the compiled model without the symbolic stages.
    Anything that needs those (a located error at the start of a run) compiles from source
    (compiler.pipeline.recompile)."""
    model: CompiledModel
    spec: str
    lib_dirs: tuple[str, ...]
    key: str
    needs_values: list[str]                         # used parameters declared without a value
    declarations: dict[str, Span]                   # variable name -> where it is declared
    notes: list[str]                                # what `dyadc simulate` prints before the run
    timings: dict[str, float] = field(default_factory=dict)
    unit_findings: list | None = None               # compiler.units findings (dicts); None: not checked

    dynamic = False                                 # state-set-switching models are not cached

    @property
    def cache_key(self) -> str:
        return self.key


def models_folder(root: Path | None = None) -> Path | None:
    root = cache_root() if root is None else root
    return None if root is None else root / MODELS_FOLDER


def request_key(spec: str, lib_dirs: Sequence[str]) -> str:
    """The lookup key: the spec, the search path (a bad -L folder is the usual located error)
    and the compiler."""
    from compiler.model.library_path import search_path
    roots = [(str(r.path), r.origin, r.runs_code) for r in search_path(lib_dirs)]
    return keys.lookup_key(spec, roots, {"entry format": ENTRY_FORMAT})


def load(spec: str, lib_dirs: Sequence[str] = ()) -> CachedCompilation | None:
    """The cached compilation of `spec` if every source it read is unchanged, else None."""
    folder = models_folder()
    if folder is None:
        return None
    began = time.perf_counter()
    lookup = request_key(spec, lib_dirs)
    manifest = _read_json(folder / f"{lookup}{MANIFEST_SUFFIX}")
    if manifest is None or manifest.get("format") != ENTRY_FORMAT:
        return None
    try:
        recorded = [(str(kind), str(path), str(value)) for kind, path, value in manifest["inputs"]]
    except (KeyError, TypeError, ValueError):
        return None
    if any(keys.fingerprint(kind, path) != value for kind, path, value in recorded):
        return None
    key = keys.entry_key(lookup, recorded)
    if key != manifest.get("entry"):
        return None
    found = read_entry(key, folder)
    if found is None:
        return None
    model, needs_values, declarations, notes, unit_findings = found
    _touch(folder / f"{key}{ENTRY_SUFFIX}")
    return CachedCompilation(model, spec, tuple(lib_dirs), key, needs_values, declarations, notes,
                             {"cache": time.perf_counter() - began}, unit_findings)


def read_entry(key: str, folder: Path | None = None) -> tuple[CompiledModel, list, dict, list, list | None] | None:
    """(model, parameters needing values, declarations, notes, unit findings) of entry `key`, or
    None if it is missing or damaged."""
    folder = models_folder() if folder is None else folder
    if folder is None:
        return None
    data = _read_json(folder / f"{key}{ENTRY_SUFFIX}")
    if data is None or data.get("format") != ENTRY_FORMAT:
        return None
    try:
        model = CompiledModel.from_dict(data["model"])
        declarations = {name: Span(**span) for name, span in data["declarations"].items()}
        findings = data.get("unit_findings")
        return (model, [str(n) for n in data["needs_values"]], declarations,
                [str(n) for n in data["notes"]], None if findings is None else list(findings))
    except Exception as err:      # a cache never fails a compile: the model is compiled again
        # The key covers the compiler's files and CasADi's version, so a sealed entry of the current
        # format that does not rebuild is a bug or a file edited by hand: say so, then miss.
        logger.warning("the cached model %s does not load (%s: %s); compiling it again", key,
                       type(err).__name__, err)
        return None


def store(spec: str, lib_dirs: Sequence[str], recorded: list[tuple[str, str, str]], compilation,
          notes: list[str]) -> str | None:
    """Write `compilation` and its `notes` under the hash of the (kind, path, fingerprint) inputs
    `recorded` as the compile read them (recording.RecordingLibrary.recorded_inputs); its entry
    key, or None when the cache is off or a source is no longer the version the compile read (it
    was edited while the compile ran: the compile may have read either version)."""
    folder = models_folder()
    if folder is None:
        return None
    if any(kind != "folder" and keys.fingerprint(kind, path) != value for kind, path, value in recorded):
        return None
    lookup = request_key(spec, lib_dirs)
    key = keys.entry_key(lookup, recorded)
    private_folder(folder)
    entry = {"format": ENTRY_FORMAT, "model": compilation.model.to_dict(),
             "needs_values": _needs_values(compilation), "declarations": _declarations(compilation.flat),
             "notes": list(notes), "unit_findings": _unit_findings(compilation.flat)}
    write_sealed(folder / f"{key}{ENTRY_SUFFIX}", _dumps(entry))
    manifest = {"format": ENTRY_FORMAT, "spec": keys.normalized_spec(spec), "entry": key,
                "inputs": [list(item) for item in recorded]}
    write_sealed(folder / f"{lookup}{MANIFEST_SUFFIX}", _dumps(manifest))
    prune(folder)
    return key


def prune(folder: Path, limit: int | None = None) -> list[Path]:
    """Delete the least recently used files of `folder` until it holds under three quarters of
    `limit` bytes (default MAX_FOLDER_BYTES) once it holds more, and temporary files of killed
    writers. A manifest whose entry is gone, or an entry without its manifest, is only a miss."""
    limit = MAX_FOLDER_BYTES if limit is None else limit
    now = time.time()
    files, removed = [], []
    for path in folder.iterdir():
        try:
            info = path.stat()
        except OSError:
            continue
        if path.name.startswith(".") and ".tmp" in path.name:
            if now - info.st_mtime > STALE_TEMPORARY_SECONDS:
                path.unlink(missing_ok=True)
                removed.append(path)
            continue
        if path.is_file() and path.name != ".lock":
            files.append((info.st_mtime, info.st_size, path))
    total = sum(size for _, size, _ in files)
    if total <= limit:
        return removed
    for _, size, path in sorted(files, key=lambda item: item[0]):
        if total <= limit * 3 // 4:
            break
        path.unlink(missing_ok=True)
        removed.append(path)
        total -= size
    return removed


def _touch(path: Path) -> None:
    try:
        os.utime(path)
    except OSError:
        pass


def _needs_values(compilation) -> list[str]:
    used = {p.name for p in compilation.reduced.parameters}
    return sorted(p.name for p in compilation.flat.parameters
                  if p.name in used and p.value is None and p.default is None)


_SPAN_FIELDS = tuple(f.name for f in dataclasses.fields(Span))


def _declarations(flat) -> dict[str, dict]:
    out = {}
    for variable in flat.variables:
        span = getattr(variable.origin, "span", None)
        if span is not None:        # dataclasses.asdict, without its deep copy (5x faster here)
            out[variable.name] = {name: getattr(span, name) for name in _SPAN_FIELDS}
    return out


def _unit_findings(flat) -> list[dict] | None:
    findings = getattr(flat, "unit_findings", None)
    return None if findings is None else [finding.to_dict() for finding in findings]


def _dumps(data: dict) -> bytes:
    return json.dumps(data, sort_keys=True, separators=(",", ":"), allow_nan=True).encode()


def _read_json(path: Path) -> dict | None:
    payload = read_sealed(path)
    if payload is None:
        return None
    try:
        data = json.loads(payload)
    except ValueError:
        return None
    return data if isinstance(data, dict) else None
