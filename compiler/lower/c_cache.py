"""The cache of compiled C libraries (`--codegen c`): one validated entry per content key.

Folder: $DYADC_CACHE or ~/.cache/dyadc, made private (mode 0700); a folder owned by another user
is refused. An entry is `dyad_<key>.so` plus `dyad_<key>.json`, which records the library's size
and SHA-256 and is written after it: a library is used only when both agree. A truncated library
would otherwise be mapped by dlopen and kill the process with SIGBUS on first use; an empty one
failed to load on every run and left the model on the slow virtual machine for good.

Writers hold an exclusive lock on `<folder>/.lock` while they check, build and record, so two
processes that need the same entry build it once. Everything a writer makes appears under its
final name by `os.replace` only, never half-written; and under the lock no other build is
running, so every leftover build folder or temp file is from a run that was killed: it goes.
"""
from __future__ import annotations

import contextlib
import hashlib
import json
import os
import shutil
import stat
import tempfile
from pathlib import Path
from typing import Callable, Iterator

try:
    import fcntl
except ImportError:      # no advisory locks (Windows): atomic replaces still keep entries whole
    fcntl = None

ENTRY_FORMAT = 1
BUILD_PREFIX = "build-"
_OLD_BUILD_PREFIX = "dyadc-cc-"        # build folders of dyadc versions before the validated cache


class CacheError(RuntimeError):
    """The cache folder cannot be used (owned by someone else, not a folder, ...)."""


def cache_dir() -> Path:
    configured = os.environ.get("DYADC_CACHE")
    return Path(configured) if configured else Path.home() / ".cache" / "dyadc"


def private_folder(folder: Path) -> Path:
    """`folder`, created if missing, owned by this user and closed to everyone else (0700)."""
    folder.mkdir(mode=0o700, parents=True, exist_ok=True)
    info = folder.stat()
    if not stat.S_ISDIR(info.st_mode):
        raise CacheError(f"the C cache {folder} is not a folder")
    if hasattr(os, "getuid") and info.st_uid != os.getuid():
        raise CacheError(f"the C cache {folder} belongs to another user; set DYADC_CACHE to a "
                         "folder of your own")
    if stat.S_IMODE(info.st_mode) & 0o077:
        folder.chmod(0o700)
    return folder


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
    with _build_lock(folder):
        found = valid_entry(folder, key)          # another process may have built it meanwhile
        if found is not None:
            return found, False
        remove_leftovers(folder)
        scratch = Path(_make_scratch(folder))
        try:
            built = build(scratch)
            library = library_path(folder, key)
            record = {"format": ENTRY_FORMAT, "size": built.stat().st_size, "sha256": _sha256(built)}
            os.replace(built, library)
            _replace_text(_record_path(folder, key), json.dumps(record, sort_keys=True) + "\n")
        finally:
            shutil.rmtree(scratch, ignore_errors=True)
    return library, True


def discard(folder: Path, key: str) -> None:
    """Forget entry `key` (a library that passed its checks but does not load): rebuilt next time."""
    with _build_lock(folder):
        for path in (_record_path(folder, key), library_path(folder, key)):
            with contextlib.suppress(FileNotFoundError):
                path.unlink()


def remove_leftovers(folder: Path) -> list[Path]:
    """Delete what killed runs left: build folders, temp files, libraries without a record.
    Call only while holding the build lock (no live build then owns any of them)."""
    removed = []
    for path in folder.iterdir():
        name = path.name
        if path.is_dir() and name.startswith((BUILD_PREFIX, _OLD_BUILD_PREFIX)):
            shutil.rmtree(path, ignore_errors=True)
        elif name.endswith(".tmp") or (name.startswith("dyad_") and name.endswith(".so")
                                       and not path.with_suffix(".json").exists()):
            path.unlink(missing_ok=True)
        else:
            continue
        removed.append(path)
    return removed


def _make_scratch(folder: Path) -> str:
    return tempfile.mkdtemp(prefix=BUILD_PREFIX, dir=folder)


def _replace_text(path: Path, text: str) -> None:
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        tmp.write_text(text, encoding="utf-8")
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


@contextlib.contextmanager
def _build_lock(folder: Path) -> Iterator[None]:
    if fcntl is None:
        yield
        return
    descriptor = os.open(folder / ".lock", os.O_RDWR | os.O_CREAT, 0o600)
    try:
        fcntl.flock(descriptor, fcntl.LOCK_EX)       # released by the kernel if this process dies
        yield
    finally:
        os.close(descriptor)
