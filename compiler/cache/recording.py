"""A library that notes every source it reads and every place it looks, for the cache's key.

It is the library the compiler always uses (compiler.model.library.Library), with its reads and
lookups observed: every file parsed or scanned for a definition header, every qualified name
searched (each searched folder of each root, found or not: a file added there later could define
the name), every package whose `dyad_functions.py` was looked for, every package folder whose
Julia sources were read.

Each source is fingerprinted when the compile first reads it, not when the compile is stored: the
key then names the version that was read, and a source whose fingerprint changed by the time of the
store (edited while the compile ran) tells the store not to keep the compile (models.store). No
clock is involved, so whether a compile is kept never depends on how soon after a file's last
write it began (a warm process starts compiling within a millisecond of a test writing its model).
"""
from __future__ import annotations

import os
from pathlib import Path

from compiler.cache.keys import Input, fingerprint
from compiler.model.library import FUNCTION_PLUGIN_FILE, Library


class RecordingLibrary(Library):
    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.read_files: set[str | os.PathLike] = set()
        self.searched_names: set[str] = set()
        self.plugin_packages: set[str] = set()
        self.julia_folders: set[Path] = set()
        self.read_fingerprints: dict[Input, str] = {}     # as first read, before the read

    def _note_read(self, kind: str, path: str | os.PathLike) -> None:
        source = (kind, str(Path(path).resolve()))
        if source not in self.read_fingerprints:
            self.read_fingerprints[source] = fingerprint(*source)

    # Paths are noted as given and resolved once in inputs(): the library reads the same texts
    # hundreds of times.
    def parse(self, path: str | os.PathLike):
        if path not in self.read_files:
            self.read_files.add(path)
            self._note_read("file", path)
        return super().parse(path)

    def source_text(self, path: Path) -> str:
        if path not in self.read_files:
            self.read_files.add(path)
            self._note_read("file", path)
        return super().source_text(path)

    def find(self, qualified_name: str):
        self.searched_names.add(qualified_name)
        return super().find(qualified_name)

    def julia_functions_in(self, folder: Path, package: str) -> dict:
        self.julia_folders.add(Path(folder).resolve())
        self._note_read("julia", folder)
        return super().julia_functions_in(folder, package)

    def plugin_files(self, qualified_name: str, runs_code: bool) -> list[Path]:
        if qualified_name not in self.plugin_packages:
            self.plugin_packages.add(qualified_name)
            package_parts = qualified_name.split(".")[:-1]
            for root in self.roots:
                self._note_read("plugin", root.joinpath(*package_parts) / FUNCTION_PLUGIN_FILE)
        return super().plugin_files(qualified_name, runs_code)

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

    def recorded_inputs(self) -> list[tuple[str, str, str]]:
        """inputs() with their fingerprints: a source's as it was when the compile first read it
        (a folder's, or a plugin looked for in a root added later, as it is now)."""
        return [(kind, path, self.read_fingerprints.get((kind, path)) or fingerprint(kind, path))
                for kind, path in self.inputs()]
