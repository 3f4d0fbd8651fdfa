"""Write a file through a temporary sibling and os.replace, so a reader never sees half a file."""
from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Callable


def write_atomically(path: str | os.PathLike, write: Callable[[str], None]) -> Path:
    """Call `write(temp_path)` and move the result onto `path`; the temporary keeps the suffix
    because writers such as matplotlib pick the format from it."""
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    handle, temp_path = tempfile.mkstemp(prefix=f".{target.stem}.", suffix=target.suffix, dir=target.parent)
    os.close(handle)
    try:
        write(temp_path)
        # mkstemp creates the file private (0600); the output gets the mode a plain open() gives.
        os.chmod(temp_path, 0o666 & ~_current_umask())
        os.replace(temp_path, target)
    except BaseException:
        if os.path.exists(temp_path):
            os.unlink(temp_path)
        raise
    return target


def _current_umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
