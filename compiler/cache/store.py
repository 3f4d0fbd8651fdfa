"""Where the compilation cache lives and how its files are written and read.

The folder is $DYADC_CACHE_DIR, else the user's cache directory (platformdirs: ~/.cache/dyadc on
Linux, ~/Library/Caches/dyadc on macOS, %LOCALAPPDATA%\\dyadc\\Cache on Windows);
DYADC_CACHE_DIR=off turns the cache off. It holds `models/` (compiled models and the manifests
that find them), `parsed/` (trees of parsed source files, parsed.py) and `c/` (shared libraries
of compiled C, c_libraries.py).

Every folder is private (0700, refused when owned by another user), every file 0600. A file is
sealed: one JSON header line with the size and SHA-256 of the payload that follows. It is written
to a temporary file that then replaces its name, so a reader sees a whole old file or a whole new
one, never half of one, and two processes writing the same entry both succeed. A file whose header does not match its payload is treated as missing and rebuilt.
"""
from __future__ import annotations

import contextlib
import hashlib
import json
import os
import stat
from pathlib import Path
from typing import Iterator

CACHE_DIR_VARIABLE = "DYADC_CACHE_DIR"
OFF_VALUES = ("off", "none", "0", "false", "no")
SEAL_FORMAT = 1
FILE_MODE = 0o600
APP_NAME = "dyadc"

try:
    import fcntl
except ImportError:      # no advisory locks (Windows): atomic replaces still keep files whole
    fcntl = None


class CacheError(RuntimeError):
    """The cache folder cannot be used (owned by someone else, not a folder, ...)."""


def cache_root() -> Path | None:
    """The cache folder, or None when DYADC_CACHE_DIR turns the cache off."""
    configured = os.environ.get(CACHE_DIR_VARIABLE)
    if configured is not None and configured.strip().lower() in OFF_VALUES:
        return None
    if configured:
        return Path(configured).expanduser()
    import platformdirs       # only here: a configured folder needs no lookup
    return Path(platformdirs.user_cache_dir(APP_NAME, appauthor=False))


def private_folder(folder: Path) -> Path:
    """`folder`, created if missing, owned by this user and closed to everyone else (0700);
    the folders created on the way to it are private too."""
    if not folder.parent.exists():
        private_folder(folder.parent)
    folder.mkdir(mode=0o700, exist_ok=True)
    info = folder.stat()
    if not stat.S_ISDIR(info.st_mode):
        raise CacheError(f"the cache {folder} is not a folder")
    if hasattr(os, "getuid") and info.st_uid != os.getuid():
        raise CacheError(f"the cache {folder} belongs to another user; set {CACHE_DIR_VARIABLE} to a "
                         "folder of your own")
    if stat.S_IMODE(info.st_mode) & 0o077:
        folder.chmod(0o700)
    return folder


def digest(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def write_sealed(path: Path, payload: bytes, mode: int = FILE_MODE) -> None:
    """`payload` under `path` behind its checksum header, atomically, readable by this user only
    (`mode`: wider for the files an installation ships, library_trees.py).

    Written to a private temporary file (`.NAME.XXXX.tmp`, which prune() removes when a killed
    writer left it) that then replaces `path`. Not flushed to the disk first (fsync cost 5-15 ms
    a file): a file that a crash left short or empty does not match its seal, and a file that
    does not match is a miss."""
    import tempfile             # writes only: a cache hit reads
    header = json.dumps({"format": SEAL_FORMAT, "size": len(payload), "sha256": digest(payload)},
                        sort_keys=True).encode() + b"\n"
    handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(handle, "wb") as out:
            out.write(header)
            out.write(payload)
        os.chmod(temporary, mode)                # mkstemp gives 0600 already; a umask cannot widen it
        os.replace(temporary, path)
    except BaseException:
        try:
            os.unlink(temporary)
        except OSError:
            pass
        raise


def read_sealed(path: Path) -> bytes | None:
    """The payload of a sealed file, or None if it is missing, truncated or damaged."""
    try:
        data = path.read_bytes()
    except OSError:
        return None
    header, newline, payload = data.partition(b"\n")
    if not newline:
        return None
    try:
        seal = json.loads(header)
    except ValueError:
        return None
    if (not isinstance(seal, dict) or seal.get("format") != SEAL_FORMAT
            or seal.get("size") != len(payload) or seal.get("sha256") != digest(payload)):
        return None
    return payload


@contextlib.contextmanager
def folder_lock(folder: Path, name: str = ".lock", shared: bool = False) -> Iterator[None]:
    """A lock on `<folder>/<name>`, exclusive unless `shared` (held by any number of processes,
    none of them while it is held exclusively); released by the kernel if this process dies."""
    if fcntl is None:
        yield
        return
    descriptor = os.open(folder / name, os.O_RDWR | os.O_CREAT, FILE_MODE)
    try:
        fcntl.flock(descriptor, fcntl.LOCK_SH if shared else fcntl.LOCK_EX)
        yield
    finally:
        os.close(descriptor)
