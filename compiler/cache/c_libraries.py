"""The cache of compiled C libraries (the default code of runs, native.py): one validated entry per
content key.

Folder: `c/` in the compilation cache (store.py: $DYADC_CACHE_DIR, else the user's
cache directory), or $DYADC_CACHE when set (the older name, for this folder alone); made private
(mode 0700), a folder owned by another user is refused. With the cache turned off
(DYADC_CACHE_DIR=off) libraries are built in a temporary folder removed when the process ends.

An entry is `dyad_<key>.so` (mode 0700) plus `dyad_<key>.json` (0600), which records the
library's size and SHA-256 and is written after it: a library is used only when both agree. A truncated library
would otherwise be mapped by dlopen and kill the process with SIGBUS on first use; an empty one
failed to load on every run and left the model on the slow virtual machine for good.

A writer holds an exclusive lock on its entry, `<folder>/dyad_<key>.lock`, while it checks,
builds and records, so two processes (or threads) that need the same entry build it once, while
different entries build at once; and a shared lock on `<folder>/.lock`, which `dyadc cache clear`
takes exclusively. Everything a writer makes appears under its final name by `os.replace` only,
never half-written; under the entry's lock no other build of that entry is running, so a
leftover build folder or temp file of that entry is from a run that was killed: it goes (and so
does any leftover over an hour old, longer than a build may take).
"""
from __future__ import annotations

import atexit
import contextlib
import hashlib
import json
import os
import shutil
import tempfile
import time
from pathlib import Path
from typing import Callable, Iterator

from compiler.cache.store import CacheError, cache_root, folder_lock, private_folder

C_CACHE_VARIABLE = "DYADC_CACHE"

# 2: a library holds the per-point functions (outputs, algebraic Newton step) besides the DAE and
# its Jacobian; an entry of format 1 fails validation, so a cached model's link to it
# (compiler/cache/native.py) leads to a rebuild instead of a library without them
ENTRY_FORMAT = 2
BUILD_PREFIX = "build-"
_OLD_BUILD_PREFIX = "dyadc-cc-"        # build folders of dyadc versions before the validated cache
STALE_AFTER = 3600                     # seconds: no build takes this long (COMPILE_TIMEOUT is 600)

__all__ = ["CacheError", "cache_dir", "discard", "fetch_or_build", "private_folder", "valid_entry"]
_scratch_cache: list[Path] = []       # the temporary folder used while the cache is turned off


def cache_dir() -> Path:
    configured = os.environ.get(C_CACHE_VARIABLE)
    if configured:
        return Path(configured)
    root = cache_root()
    if root is not None:
        return root / "c"
    if not _scratch_cache:
        _scratch_cache.append(Path(tempfile.mkdtemp(prefix="dyadc-c-")))
        atexit.register(shutil.rmtree, _scratch_cache[0], True)
    return _scratch_cache[0]


def library_path(folder: Path, key: str) -> Path:
    return folder / f"dyad_{key}.so"


def _record_path(folder: Path, key: str) -> Path:
    return folder / f"dyad_{key}.json"


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def valid_entry(folder: Path, key: str) -> Path | None:
    """The library of entry `key` if its size and checksum match the record written with it."""
    library = library_path(folder, key)
    try:
        record = json.loads(_record_path(folder, key).read_text(encoding="utf-8"))
        if (not isinstance(record, dict) or record.get("format") != ENTRY_FORMAT
                or record.get("size") != library.stat().st_size or record.get("sha256") != _sha256(library)):
            return None
    except (OSError, ValueError):
        return None
    return library


def fetch_or_build(folder: Path, key: str, build: Callable[[Path], Path]) -> tuple[Path, bool]:
    """(library, built now) for entry `key`: the valid cached one, or `build(scratch_folder)`'s
    result recorded as the new entry. `build` returns the library it made inside the folder."""
    found = valid_entry(folder, key)
    if found is not None:
        return found, False
    private_folder(folder)
    with _entry_lock(folder, key):
        found = valid_entry(folder, key)          # another process may have built it meanwhile
        if found is not None:
            return found, False
        remove_leftovers(folder, key)
        built, scratch = _build_in_new_folder(folder, key, build)
        try:
            library = library_path(folder, key)
            record = {"format": ENTRY_FORMAT, "size": built.stat().st_size, "sha256": _sha256(built)}
            built.chmod(0o700)                    # private, like everything in the cache
            os.replace(built, library)
            _replace_text(_record_path(folder, key), json.dumps(record, sort_keys=True) + "\n")
        finally:
            shutil.rmtree(scratch, ignore_errors=True)
    return library, True


def _build_in_new_folder(folder: Path, key: str, build: Callable[[Path], Path]) -> tuple[Path, Path]:
    """(library, its build folder): `build` run in a new build folder; run once more, the folders
    made again, when its folder or the whole cache folder went away under it (nothing of ours
    removes either while the entry's lock is held; a cleaner of old files in /tmp can)."""
    def attempt() -> tuple[Path, Path] | None:
        private_folder(folder)
        scratch = Path(tempfile.mkdtemp(prefix=f"{BUILD_PREFIX}{key}-", dir=folder))
        try:
            return build(scratch), scratch
        except (OSError, RuntimeError):
            gone = not scratch.is_dir()
            shutil.rmtree(scratch, ignore_errors=True)
            if not gone:
                raise
            return None

    first = attempt()
    if first is not None:
        return first
    second = attempt()
    if second is None:
        raise FileNotFoundError(f"the build folder of {key} in {folder} went away twice under its build")
    return second


def discard(folder: Path, key: str) -> None:
    """Forget entry `key` (a library that passed its checks but does not load): rebuilt next time."""
    with _entry_lock(folder, key):
        for path in (_record_path(folder, key), library_path(folder, key)):
            with contextlib.suppress(FileNotFoundError):
                path.unlink()


def remove_leftovers(folder: Path, key: str) -> list[Path]:
    """Delete what killed runs left: build folders, temp files, libraries without a record, of
    entry `key` (call only while holding its lock: no live build then owns them), and those of
    any entry once they are older than STALE_AFTER."""
    removed = []
    stale_before = time.time() - STALE_AFTER
    for path in folder.iterdir():
        name = path.name
        if not (name.startswith((f"{BUILD_PREFIX}{key}-", f".dyad_{key}.", f"dyad_{key}."))
                or _modified_before(path, stale_before)):
            continue
        if path.is_dir() and name.startswith((BUILD_PREFIX, _OLD_BUILD_PREFIX)):
            shutil.rmtree(path, ignore_errors=True)
        elif name.endswith(".tmp") or (name.startswith("dyad_") and name.endswith(".so")
                                       and not path.with_suffix(".json").exists()):
            path.unlink(missing_ok=True)
        else:
            continue
        removed.append(path)
    return removed


def _modified_before(path: Path, moment: float) -> bool:
    """Whether `path` was last modified before `moment`; False once it is gone: another entry's
    build removes its own folder and temp files between this folder's listing and the look."""
    try:
        return path.lstat().st_mtime < moment
    except FileNotFoundError:
        return False


def _replace_text(path: Path, text: str) -> None:
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        with os.fdopen(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600), "w",
                       encoding="utf-8") as out:
            out.write(text)
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


@contextlib.contextmanager
def _entry_lock(folder: Path, key: str) -> Iterator[None]:
    """The folder's lock shared (`dyadc cache clear` waits), then the entry's own exclusive lock;
    both released by the kernel if this process dies."""
    with folder_lock(folder, shared=True), folder_lock(folder, f"dyad_{key}.lock"):
        yield
