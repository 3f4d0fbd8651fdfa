"""The parse cache (compiler/cache/parsed.py, docs/cache.md): trees of parsed files kept between
runs as plain JSON data (compiler/cache/ast_codec.py). A tree read back is the parsed tree field
for field, spans and number literals included; an edited, damaged or unparsable file is parsed
as without the cache; a compile that finds every source file in it does not import lark."""
from __future__ import annotations

import dataclasses
import json
import os
import stat
from pathlib import Path

import pytest

from compiler.cache import ast_codec, parsed
from compiler.errors import DyadError, Span
from compiler.syntax import ast
from compiler.syntax.parser import parse_file, parse_source
from tests.cache.helpers import ROOT, dyadc, entries, retried_if_the_compiler_changes, small_library, write

LIBRARY_FILES = sorted((ROOT / "components").rglob("*.dyad")) + sorted((ROOT / "tests" / "models").rglob("*.dyad"))


def every_field(tree) -> list:
    """`tree` as a flat list of (type, value) in a fixed order, every field included (AST
    equality leaves spans and literals out), without recursion."""
    out, stack = [], [tree]
    while stack:
        value = stack.pop()
        if dataclasses.is_dataclass(value):
            out.append(type(value).__name__)
            stack.extend(getattr(value, f.name) for f in reversed(dataclasses.fields(value)))
        elif isinstance(value, tuple):
            out.append(("tuple", len(value)))
            stack.extend(reversed(value))
        else:
            out.append((type(value).__name__, repr(value)))
    return out


def test_every_library_and_test_model_file_reads_back_field_for_field():
    assert len(LIBRARY_FILES) > 100
    for path in LIBRARY_FILES:
        tree = parse_file(path)
        back = ast_codec.decode(ast_codec.encode(tree))
        assert back is not None, path
        assert every_field(back) == every_field(tree), path


def test_numbers_keep_their_type_and_literal_and_strings_their_characters():
    source = ('component C\n  parameter a::Real = 10k\n  parameter b::Integer = 3\n'
              '  parameter c::Real = 3e4\n  parameter d::Real = -0.0\n'
              '  variable x::Real\nrelations\n  x = a * b + c + d + 1.0\nend\n')
    tree = parse_source(source, "/nowhere/C.dyad")
    back = ast_codec.decode(ast_codec.encode(tree))
    assert every_field(back) == every_field(tree)
    fields = every_field(back)
    assert ("float", "10000.0") in fields and ("int", "3") in fields and ("str", "'10k'") in fields
    text = ast.String('ü ≤ é "quoted" \\ \n end', Span("/s.dyad", 1, 1, 1, 9))
    holder = ast.File("/s.dyad", (), (ast.ComponentDef("S", doc=text.value),), None)
    assert every_field(ast_codec.decode(ast_codec.encode(holder))) == every_field(holder)


def test_a_20000_term_sum_is_written_and_read_without_recursion():
    terms = " + ".join(f"x{i % 7}" for i in range(20000))
    tree = parse_source(f"component C\n  variable y::Real\nrelations\n  y = {terms}\nend\n", "/x/C.dyad")
    back = ast_codec.decode(ast_codec.encode(tree))
    assert back == tree and every_field(back) == every_field(tree)


def test_a_node_used_twice_stays_one_object():
    shared = ast.Number(1.0, Span("/f.dyad", 1, 1, 1, 3), "1.0")
    equation = ast.Equation(ast.BinaryOp("+", shared, shared), shared)
    tree = ast.File("/f.dyad", (), (ast.ComponentDef("C", relations=(equation,)),), None)
    back = ast_codec.decode(ast_codec.encode(tree)).definitions[0].relations[0]
    assert back.lhs.left is back.lhs.right is back.rhs
    assert every_field(back) == every_field(equation)


def test_a_span_in_another_file_is_not_encoded():
    tree = ast.File("/f.dyad", (ast.Using("P", (), Span("/other.dyad", 1, 1, 1, 5)),), (), None)
    with pytest.raises(ast_codec.NotEncodable):
        ast_codec.encode(tree)


def test_data_for_other_ast_classes_is_not_read():
    data = json.loads(ast_codec.encode(parse_file(LIBRARY_FILES[0])))
    data[0]["types"][0][1] = data[0]["types"][0][1] + ["new_field"]
    assert ast_codec.decode(json.dumps(data).encode()) is None
    data[0]["types"][0][0] = "NotANode"
    assert ast_codec.decode(json.dumps(data).encode()) is None
    assert ast_codec.decode(b"[1, 2") is None
    assert ast_codec.decode(b'[{"format": 1, "path": "/a", "types": []}, [[9, 0]]]') is None


def decay_file(folder: Path, rate: str = "2.0") -> Path:
    return write(folder / "Decay.dyad", f"""
        component Decay
          parameter k::Real = {rate}
          variable x::Real
        relations
          initial x = 1.0
          der(x) = -k * x
        end
        """)


def test_a_second_parse_of_an_unchanged_file_is_read_back(tmp_path):
    source = decay_file(tmp_path / "src")
    first = parsed.ParseCache(tmp_path / "cache" / "parsed")
    tree = first.parse(str(source))
    assert (first.hits, first.stored) == (0, 1)
    second = parsed.ParseCache(tmp_path / "cache" / "parsed")
    again = second.parse(str(source))
    assert (second.hits, second.stored) == (1, 0)
    assert every_field(again) == every_field(tree) == every_field(parse_file(source))
    folder = tmp_path / "cache" / "parsed"
    assert stat.S_IMODE(folder.stat().st_mode) == 0o700
    assert all(stat.S_IMODE(p.stat().st_mode) == 0o600 for p in folder.iterdir())


def test_an_edited_or_damaged_file_is_parsed_again(tmp_path):
    source = decay_file(tmp_path / "src")
    folder = tmp_path / "cache" / "parsed"
    parsed.ParseCache(folder).parse(str(source))
    decay_file(tmp_path / "src", rate="5.0")
    edited = parsed.ParseCache(folder)
    tree = edited.parse(str(source))
    assert (edited.hits, edited.stored) == (0, 1)
    assert every_field(tree) == every_field(parse_file(source))
    for entry in folder.iterdir():                # damage every entry: each is a miss, rewritten
        entry.write_bytes(entry.read_bytes()[:-5])
    damaged = parsed.ParseCache(folder)
    assert every_field(damaged.parse(str(source))) == every_field(parse_file(source))
    assert (damaged.hits, damaged.stored) == (0, 1)
    assert parsed.ParseCache(folder).parse(str(source)) is not None


def test_a_file_that_does_not_parse_gives_the_parser_error_and_is_not_kept(tmp_path):
    broken = write(tmp_path / "src" / "Broken.dyad", "component Broken\n  variable x::Real\nrelations\n  x = (1 +\nend\n")
    with pytest.raises(DyadError) as without:
        parse_file(broken)
    cache = parsed.ParseCache(tmp_path / "cache" / "parsed")
    with pytest.raises(DyadError) as cached:
        cache.parse(str(broken))
    assert cached.value.format() == without.value.format()
    assert cache.stored == 0
    missing = tmp_path / "src" / "Missing.dyad"
    with pytest.raises(DyadError, match="cannot read"):
        cache.parse(str(missing))


@retried_if_the_compiler_changes
def test_a_compile_from_kept_trees_imports_no_lark_and_gives_the_same_run(tmp_path):
    cache, library = tmp_path / "cache", small_library(tmp_path / "lib")
    run = ("simulate", "CacheLib.Scaled", "--stop", "1", "-L", library, "--rtol", "1e-10", "--atol", "1e-12",
           "--output", tmp_path / "first.csv")
    first = dyadc(cache, *run)
    assert first.code == 0 and "lark" in first.imported, first.stderr
    assert list((cache / "parsed").glob("*.ast"))
    for entry in entries(cache) + entries(cache, ".manifest"):
        entry.unlink()                    # the model is compiled again, from the kept trees
    second = dyadc(cache, *run[:-1], tmp_path / "second.csv")
    assert second.code == 0 and second.compiled, second.stderr
    assert "lark" not in second.imported
    assert (tmp_path / "second.csv").read_bytes() == (tmp_path / "first.csv").read_bytes()
    info = dyadc(cache, "cache", "info")
    assert "parsed source files: " in info.stdout
    assert dyadc(cache, "cache", "clear").code == 0 and not list((cache / "parsed").glob("*.ast"))


def test_nodes_built_by_their_init_read_back_the_same(monkeypatch):
    """A node class whose __init__ does more than set fields (__post_init__, slots) is built by
    it; here every class is, and the trees are the same."""
    monkeypatch.setattr(ast_codec, "_NEEDS_INIT", frozenset(ast_codec._NODE_TYPES.values()))
    for path in LIBRARY_FILES[:20]:
        tree = parse_file(path)
        assert every_field(ast_codec.decode(ast_codec.encode(tree))) == every_field(tree), path
