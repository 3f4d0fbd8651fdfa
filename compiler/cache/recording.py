"""A library that notes every source it reads and every place it looks, for the cache's key.

It is the library the compiler always uses (compiler.model.library.Library), with its reads and
lookups observed: every file parsed or scanned for a definition header, every qualified name
searched (each searched folder of each root, found or not: a file added there later could define
the name), every package whose `dyad_functions.py` was looked for, every package folder whose
Julia sources were read.
"""
from __future__ import annotations

import os
from pathlib import Path

from compiler.cache.keys import Input
from compiler.model.library import FUNCTION_PLUGIN_FILE, Library


class RecordingLibrary(Library):
    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.read_files: set[str | os.PathLike] = set()
        self.searched_names: set[str] = set()
        self.plugin_packages: set[str] = set()
        self.julia_folders: set[Path] = set()

    # Paths are noted as given and resolved once in inputs(): the library reads the same texts
    # hundreds of times.
    def parse(self, path: str | os.PathLike):
        self.read_files.add(path)
        return super().parse(path)

    def _text(self, path: Path) -> str:
        self.read_files.add(path)
        return super()._text(path)

    def find(self, qualified_name: str):
        self.searched_names.add(qualified_name)
        return super().find(qualified_name)

    def _julia_functions(self, folder: Path, package: str) -> dict:
        self.julia_folders.add(Path(folder).resolve())
        return super()._julia_functions(folder, package)

    def _plugins_for(self, qualified_name: str, runs_code: bool) -> list[Path]:
        self.plugin_packages.add(qualified_name)
        return super()._plugins_for(qualified_name, runs_code)

    def inputs(self) -> list[Input]:
        """Everything the compile depended on, as (kind, absolute path) pairs."""
        found: set[Input] = {("file", str(Path(path).resolve())) for path in self.read_files}
        for name in self.searched_names:
            package_parts = name.split(".")[:-1]
            found.update(("folder", str(root.joinpath(*package_parts))) for root in self.roots)
            # which root provides the top-level package (a user's package replaces a shipped one)
            found.update(("folder", str(root.joinpath(*package_parts[:1]))) for root in self.roots)
        for name in self.plugin_packages:
            package_parts = name.split(".")[:-1]
            found.update(("plugin", str(root.joinpath(*package_parts) / FUNCTION_PLUGIN_FILE))
                         for root in self.roots)
        found.update(("julia", str(folder)) for folder in self.julia_folders)
        return sorted(found)
