"""The C compiler dyadc uses, and the build of the runtime's own C routine: the CSV row formatter
(csv_rows.c) that csv_text.py loads. Standard library only, so that setup.py can run it while the
package is built, before numpy or casadi are installed: `make install` builds the library beside
csv_rows.c when a compiler is found.

The library's name carries a hash of csv_rows.c, so a library built from an older source is
never loaded (csv_text.py then formats in Python, the same text, slower).
"""
from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
from pathlib import Path

CSV_SOURCE = Path(__file__).with_name("csv_rows.c")
CSV_FLAGS = ["-O2", "-fPIC", "-shared"]
BUILD_TIMEOUT_S = 120


def find_compiler() -> str | None:
    """$CC if set, else the first of gcc, cc and clang on the PATH; None without one."""
    configured = os.environ.get("CC")
    for candidate in ([configured] if configured else []) + ["gcc", "cc", "clang"]:
        found = shutil.which(candidate)
        if found:
            return found
    return None


def csv_library_path(folder: Path | None = None) -> Path:
    """Where the library built from the current csv_rows.c lives (default: beside the source)."""
    digest = hashlib.sha256(CSV_SOURCE.read_bytes()).hexdigest()[:16]
    return (folder or CSV_SOURCE.parent) / f"csv_rows-{digest}.so"


def build_csv_library(folder: Path | None = None, compiler: str | None = None) -> Path:
    """Compile csv_rows.c into `csv_library_path(folder)`, atomically, and remove the libraries
    built there from older sources; an OSError without a C compiler, a RuntimeError when the
    build fails."""
    compiler = compiler or find_compiler()
    if compiler is None:
        raise OSError("no C compiler (gcc, cc or clang) found")
    target = csv_library_path(folder)
    temp = target.with_name(f".{target.name}.{os.getpid()}.tmp")
    try:
        done = subprocess.run([compiler, *CSV_FLAGS, str(CSV_SOURCE), "-o", str(temp)],
                              capture_output=True, text=True, timeout=BUILD_TIMEOUT_S)
        if done.returncode != 0:
            raise RuntimeError(f"{Path(compiler).name} failed: {done.stderr.strip()[-2000:]}")
        os.replace(temp, target)
    finally:
        temp.unlink(missing_ok=True)
    for old in target.parent.glob("csv_rows-*.so"):
        if old != target:
            old.unlink(missing_ok=True)
    return target
