"""The shipped library's trees made at install (compiler/cache/library_trees.py, docs/cache.md): a
file whose text has a tree reads it back field for field as the parser gives it, at the path the
run found it; another text, a damaged tree or a missing folder is parsed; a compile through them
gives the same model as the parser."""
from __future__ import annotations

import stat

from compiler.cache import library_trees
from compiler.pipeline import compile_spec
from compiler.model.library import Library
from compiler.syntax.parser import parse_file
from tests.cache.helpers import small_library
from tests.cache.test_parse_cache import every_field


def test_a_tree_made_at_install_is_the_parsed_tree_at_the_path_it_is_read_for(tmp_path):
    library = small_library(tmp_path / "lib")
    folder = tmp_path / "trees"
    sources = sorted(library.rglob("*.dyad"))
    assert library_trees.write_trees(library, folder) == len({p.read_text() for p in sources}) > 0
    for path in sources:
        tree = library_trees.find(str(path), path.read_text(), folder)
        assert tree is not None and tree.path == str(path)
        assert every_field(tree) == every_field(parse_file(path)), path
        assert library_trees.find(str(path), path.read_text() + "\n", folder) is None   # another text
    text = sources[0].read_text()
    entry = folder / f"{library_trees.tree_key(text)}{library_trees.TREE_SUFFIX}"
    assert stat.S_IMODE(entry.stat().st_mode) == library_trees.INSTALLED_MODE
    entry.write_bytes(entry.read_bytes()[:-3])                  # damaged: not used
    assert library_trees.find(str(sources[0]), text, folder) is None
    assert library_trees.find(str(sources[0]), text, tmp_path / "none") is None


def test_trees_of_texts_no_longer_in_the_library_are_removed(tmp_path):
    library = small_library(tmp_path / "lib")
    folder = tmp_path / "trees"
    library_trees.write_trees(library, folder)
    edited = sorted(library.rglob("*.dyad"))[0]
    old_key = library_trees.tree_key(edited.read_text())
    edited.write_text(edited.read_text() + "\n")
    library_trees.write_trees(library, folder)
    assert not (folder / f"{old_key}.ast").exists()
    assert (folder / f"{library_trees.tree_key(edited.read_text())}.ast").exists()


def test_a_compile_from_the_trees_gives_the_model_of_the_parser(tmp_path, monkeypatch):
    library = tmp_path / "lib"
    spec = "CacheLib.Scaled"
    small_library(library)
    folder = tmp_path / "trees"
    library_trees.write_trees(library, folder)
    monkeypatch.setattr(library_trees, "TREES_FOLDER", folder)
    monkeypatch.setattr(library_trees.find, "__defaults__", (folder,))
    parsed = compile_spec(spec, [str(library)], library=Library([str(library)], parser=parse_file))
    import compiler.syntax.parser

    def no_parse(path):
        raise AssertionError(f"{path} parsed although it has a tree")

    monkeypatch.setattr(compiler.syntax.parser, "parse_file", no_parse)
    trees = Library([str(library)], parser=library_trees.parse_file)
    from_trees = compile_spec(spec, [str(library)], library=trees)
    assert trees.parse_count > 0
    assert str(from_trees.flat.equations) == str(parsed.flat.equations)
    assert from_trees.model.to_dict() == parsed.model.to_dict()
