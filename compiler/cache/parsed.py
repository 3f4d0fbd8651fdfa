"""Parsed source files kept between runs: `<root>/parsed/<key>.ast`, one per file version.

A compile that misses the model cache (a model seen for the first time, or one whose own file was
edited) still reads the library files an earlier compile read; their trees come from here instead
of the parser, so such a compile imports neither lark nor the parser (docs/cache.md). The key
hashes the compiler's fingerprint (keys.compiler_fingerprint: any edit of dyadc, the grammar
included, changes it), the file's path (spans name it) and the text the parser would read
(`Path.read_text`, as compiler.syntax.parser.parse_file reads it): a file whose text changed
has a new key. The entry is sealed (store.py) and holds the tree as plain JSON data
(ast_codec.py, never pickle); a damaged or unreadable one is parsed again and rewritten.

A file that does not parse is not kept: parse_file raises its located error as without the cache.
A file whose text is one of the shipped library's, as installed, takes the tree made at install
(library_trees.py) and is not kept here again.
"""
from __future__ import annotations

from pathlib import Path

from compiler.cache import ast_codec, keys, library_trees
from compiler.cache.store import CacheError, cache_root, private_folder, read_sealed, write_sealed

PARSED_FOLDER = "parsed"
PARSED_SUFFIX = ".ast"
# Pruned like models/ (least recently used first), to three quarters of this size.
MAX_FOLDER_BYTES = 128 * 1024 * 1024


def parsed_folder(root: Path | None = None) -> Path | None:
    root = cache_root() if root is None else root
    return None if root is None else root / PARSED_FOLDER


def open_cache() -> "ParseCache | None":
    """The parse cache of the cache folder, or None when the cache is off."""
    folder = parsed_folder()
    return None if folder is None else ParseCache(folder)


class ParseCache:
    """`parse(path)` as compiler.syntax.parser.parse_file, with trees kept in `folder`."""

    def __init__(self, folder: Path):
        self.folder = folder
        self.hits = 0
        self.shipped_hits = 0
        self.stored = 0

    def key(self, path: str, text: str) -> str:
        return keys.hash_text("parsed", keys.compiler_fingerprint(), path,
                              keys.hash_text(text))

    def parse(self, path):
        from compiler.errors import register_source
        path = Path(path)
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError):
            return _parse_file(path)         # its located error
        shipped = library_trees.find(str(path), text)
        if shipped is not None:              # a file of the shipped library, as installed
            register_source(str(path), text)
            self.shipped_hits += 1
            return shipped
        entry = self.folder / f"{self.key(str(path), text)}{PARSED_SUFFIX}"
        payload = read_sealed(entry)
        tree = ast_codec.decode(payload) if payload is not None else None
        if tree is not None and tree.path == str(path):
            register_source(str(path), text)       # as the parser does: errors show the line
            self.hits += 1
            _touch(entry)
            return tree
        from compiler.syntax.parser import parse_source
        tree = parse_source(text, str(path))
        self._store(entry, tree)
        return tree

    def _store(self, entry: Path, tree) -> None:
        try:
            payload = ast_codec.encode(tree)
        except ast_codec.NotEncodable:
            return
        try:
            private_folder(self.folder)
            write_sealed(entry, payload)
        except (OSError, CacheError):
            return                          # a cache that cannot be written is only slower
        self.stored += 1

    def prune(self) -> None:
        from compiler.cache.models import prune
        if self.stored and self.folder.is_dir():
            try:
                prune(self.folder, MAX_FOLDER_BYTES)
            except OSError:
                pass


def _parse_file(path: Path):
    from compiler.syntax.parser import parse_file
    return parse_file(path)


def _touch(path: Path) -> None:
    import os
    try:
        os.utime(path)
    except OSError:
        pass
