"""The parsed trees of the shipped library, made when dyadc is installed (like Python's .pyc files).

A user's first compile reads about twenty files of the shipped library, and parsing them (importing
lark, loading the LALR tables) costs more than the model itself (docs/cache.md). Building the
wheel (and `pip install .`, `pip install -e .`, `make install`: setup.py runs `write_trees`)
parses every `.dyad` file of `components/` once and keeps its tree in
`compiler/cache/shipped_trees/<key>.ast`, sealed (store.py) and encoded as plain JSON data
(ast_codec.py, never pickle). A compile then takes the tree of a file whose text is one of these
instead of parsing it; nothing is written at run time, and a folder that is missing, unreadable or
made by another parser is only slower.

The key hashes the parser's fingerprint (the bytes of compiler/syntax/, errors.py and the codec,
Python's version) and the file's text, not its path: the tree is read back for the path the run
found the file at (its spans name that path). An edited library file, or an edited grammar, has
another key and is parsed (and kept in the user's parse cache, parsed.py).
"""
from __future__ import annotations

import hashlib
import os
import sys
from functools import lru_cache
from pathlib import Path

from compiler.cache import ast_codec
from compiler.cache.store import read_sealed, write_sealed

TREES_FOLDER = Path(__file__).resolve().parent / "shipped_trees"
TREE_SUFFIX = ".ast"
INSTALLED_MODE = 0o644        # part of the installation, readable by all its users as its .py files
_PARSER_FILES = (".py", ".lark", ".json")


@lru_cache(maxsize=None)
def parser_fingerprint() -> str:
    """A hash of everything a parsed tree depends on: the parser's package (grammar, LALR tables,
    tree builder, AST classes), the spans' class, the codec, Python's version."""
    package = Path(__file__).resolve().parents[1]
    digest = hashlib.sha256(f"python {sys.version_info[0]}.{sys.version_info[1]}\0".encode())
    files = sorted(p for p in (package / "syntax").iterdir() if p.suffix in _PARSER_FILES)
    for path in [*files, package / "errors.py", package / "cache" / "ast_codec.py"]:
        digest.update(f"{path.relative_to(package).as_posix()}\0".encode() + path.read_bytes() + b"\0")
    return digest.hexdigest()


def tree_key(text: str) -> str:
    digest = hashlib.sha256(f"shipped tree\0{parser_fingerprint()}\0".encode())
    digest.update(text.encode("utf-8", "surrogatepass"))
    return digest.hexdigest()


@lru_cache(maxsize=None)
def _available(folder: Path) -> bool:
    return folder.is_dir()


def find(path: str, text: str, folder: Path = TREES_FOLDER):
    """The shipped tree of `text`, read for the file `path`, or None."""
    if not _available(folder):
        return None
    payload = read_sealed(folder / f"{tree_key(text)}{TREE_SUFFIX}")
    return None if payload is None else ast_codec.decode(payload, path)


def parse_file(path):
    """compiler.syntax.parser.parse_file, from a shipped tree when there is one for the file's text."""
    from compiler.errors import register_source
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        text = None                          # parse_file gives the located error
    tree = None if text is None else find(str(path), text)
    if tree is None:
        from compiler.syntax.parser import parse_file as parse
        return parse(path)
    register_source(str(path), text)         # as the parser does: errors show the line
    return tree


def write_trees(library: Path, folder: Path) -> int:
    """Parse every .dyad file under `library` and keep its tree in `folder` (made if missing;
    trees of other texts or parsers are removed). Returns how many trees it holds. A file that
    does not parse is left out: a compile that reads it reports the parser's located error."""
    from compiler.errors import DyadError
    from compiler.syntax.parser import parse_source
    folder.mkdir(parents=True, exist_ok=True)
    (folder / ".gitignore").write_text("# made by setup.py (compiler/cache/library_trees.py)\n*\n")
    kept: set[str] = set()
    for source in sorted(library.rglob("*.dyad")):
        text = source.read_text(encoding="utf-8")
        name = f"{tree_key(text)}{TREE_SUFFIX}"
        if name in kept:
            continue
        try:
            payload = ast_codec.encode(parse_source(text, source.relative_to(library).as_posix()))
        except (DyadError, ast_codec.NotEncodable):
            continue
        write_sealed(folder / name, payload, mode=INSTALLED_MODE)
        kept.add(name)
    for stale in folder.glob(f"*{TREE_SUFFIX}"):
        if stale.name not in kept:
            stale.unlink()
    return len(kept)


def main(argv: list[str] | None = None) -> str:
    """`python -m compiler.cache.library_trees [LIBRARY [FOLDER]]`: the trees of LIBRARY (default:
    the source checkout's components/) into FOLDER (default: this package's shipped_trees/); the
    line that says so."""
    args = sys.argv[1:] if argv is None else argv
    library = Path(args[0]) if args else Path(__file__).resolve().parents[2] / "components"
    folder = Path(args[1]) if len(args) > 1 else TREES_FOLDER
    count = write_trees(library, folder)
    return f"{count} parsed trees of {library} in {os.fspath(folder)}"


if __name__ == "__main__":
    print(main())
