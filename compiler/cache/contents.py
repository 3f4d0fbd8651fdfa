"""What the compilation cache holds (`info_lines`) and emptying it (`clear`): `dyadc cache`."""
from __future__ import annotations

import shutil
from pathlib import Path

from compiler.cache.models import MODELS_FOLDER, ENTRY_SUFFIX
from compiler.cache.parsed import PARSED_FOLDER, PARSED_SUFFIX
from compiler.cache.store import CACHE_DIR_VARIABLE, cache_root, folder_lock


def _c_folder() -> Path:
    from compiler.cache import c_libraries
    return c_libraries.cache_dir()


def _size(folder: Path, pattern: str) -> tuple[int, int]:
    files = [p for p in folder.glob(pattern) if p.is_file()] if folder.is_dir() else []
    return len(files), sum(p.stat().st_size for p in files)


def _megabytes(size: int) -> str:
    return f"{size / 1e6:.1f} MB"


def info_lines() -> list[str]:
    root = cache_root()
    if root is None:
        return [f"the compilation cache is off ({CACHE_DIR_VARIABLE}=off)"]
    models = root / MODELS_FOLDER
    count, size = _size(models, f"*{ENTRY_SUFFIX}")
    parsed, parsed_size = _size(root / PARSED_FOLDER, f"*{PARSED_SUFFIX}")
    c_folder = _c_folder()
    libraries, library_size = _size(c_folder, "dyad_*.so")
    return [f"cache folder: {root}" + ("" if root.is_dir() else " (not created yet)"),
            f"compiled models: {count} ({_megabytes(size)}) in {models}",
            f"parsed source files: {parsed} ({_megabytes(parsed_size)}) in {root / PARSED_FOLDER}",
            f"C libraries: {libraries} ({_megabytes(library_size)}) in {c_folder}",
            f"move it with {CACHE_DIR_VARIABLE}=DIR, turn it off with {CACHE_DIR_VARIABLE}=off or "
            f"`dyadc simulate --no-cache`"]


def clear() -> list[Path]:
    """Remove every cached model, parsed file and C library; the folders themselves stay."""
    root = cache_root()
    if root is None:
        return []
    removed = []
    for folder in (root / MODELS_FOLDER, root / PARSED_FOLDER, _c_folder()):
        if not folder.is_dir():
            continue
        with folder_lock(folder):             # no C build is half-way through meanwhile
            for path in folder.iterdir():
                if path.name == ".lock":
                    continue
                if path.is_dir() and not path.is_symlink():
                    shutil.rmtree(path, ignore_errors=True)
                else:
                    path.unlink(missing_ok=True)
                removed.append(path)
    return removed
