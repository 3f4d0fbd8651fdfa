"""The parser keeps no cache outside the package (issue 19, item 1) and its packaged tables are current.

The attack: lark's `cache=True` loads `<tempdir>/.lark_cache_<user>_<hash>_<py>.tmp` with pickle, and
another local user can plant that file. Every test runs fresh Python processes with TMPDIR pointing
at the test's own folder, so the planted file sits exactly where lark would look, and nothing of the
real temp folder is touched.
"""
import json
import os
import pickle
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from compiler.syntax import lalr

REPO = Path(__file__).resolve().parents[2]


class _Payload:
    """Unpickling this runs `open(marker, "w")`: proof that code from the planted file ran."""

    def __init__(self, marker: Path):
        self.marker = str(marker)

    def __reduce__(self):
        return (open, (self.marker, "w"))


def _run(code: str, tmp_path: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ, TMPDIR=str(tmp_path), PYTHONPATH=str(REPO))
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=120)


_LEGACY_BUILD = """
    from lark import Lark
    from compiler.syntax import lalr
    options = dict(lalr._options(), cache=True)
    Lark(lalr.grammar_text(), **options)
"""


def _plant(tmp_path: Path, marker: Path) -> Path:
    """Let lark's cache=True name its cache file (the predictable path), then replace it."""
    result = _run(_LEGACY_BUILD, tmp_path)
    assert result.returncode == 0, result.stderr
    (cache_file,) = tmp_path.glob(".lark_cache_*.tmp")
    with cache_file.open("wb") as f:
        f.write(b"0" * 64 + b"\n")            # lark reads a hash line, then unpickles
        pickle.dump(_Payload(marker), f)
    return cache_file


def test_planted_grammar_cache_is_never_loaded(tmp_path):
    marker = tmp_path / "PLANTED_CODE_RAN"
    cache_file = _plant(tmp_path, marker)

    # The planted file is live: a process that still used lark's cache would run it.
    _run(_LEGACY_BUILD, tmp_path)
    assert marker.exists(), "the planted pickle should run under cache=True (test set-up)"
    marker.unlink()

    result = _run("""
        from compiler.syntax.parser import parse_source, parse_expression
        parse_source("component A\\n  variable x::Real\\nrelations\\n  der(x) = -x\\nend\\n", "a.dyad")
        parse_expression("1 + 2")
        print("parsed")
    """, tmp_path)
    assert result.returncode == 0, result.stderr
    assert "parsed" in result.stdout
    assert not marker.exists(), "dyadc loaded the planted grammar cache"
    assert cache_file.exists()


def test_parsing_writes_nothing_to_the_temp_folder(tmp_path):
    result = _run("""
        from compiler.syntax.parser import parse_source
        parse_source("component A\\nend\\n", "a.dyad")
    """, tmp_path)
    assert result.returncode == 0, result.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_packaged_tables_match_the_grammar():
    tables = lalr._read_tables()
    assert tables is not None, "compiler/syntax/lalr_tables.json is missing"
    # Judged with the lark version that wrote them: under another lark they are merely unused.
    assert tables["fingerprint"] == lalr.fingerprint(lalr.grammar_text(), tables["lark"]), (
        "the grammar changed: regenerate the tables with `python -m compiler.syntax.lalr`")


def test_packaged_tables_parse_like_a_fresh_build():
    from compiler.syntax.layout import arrange
    from compiler.syntax.parser import tokenize
    loaded, built = lalr.load_parser(), lalr.build_parser()
    sources = sorted((REPO / "tests" / "syntax" / "valid").glob("*.dyad"))
    sources += sorted((REPO / "components").rglob("*.dyad"))[:40]
    assert sources
    for path in sources:
        tokens = arrange(tokenize(path.read_text(encoding="utf-8"), str(path)))
        assert (loaded.parse(list(tokens), start="start").pretty()
                == built.parse(list(tokens), start="start").pretty()), path


@pytest.mark.parametrize("current", [False, True], ids=["stale", "damaged"])
def test_stale_or_damaged_tables_fall_back_to_a_fresh_build(tmp_path, monkeypatch, current):
    damaged = tmp_path / "tables.json"
    stamp = lalr.fingerprint(lalr.grammar_text()) if current else "0"
    damaged.write_text(json.dumps({"fingerprint": stamp, "data": {}, "memo": {}}), encoding="utf-8")
    monkeypatch.setattr(lalr, "TABLES_PATH", damaged)
    parser = lalr.load_parser()
    assert parser.parse([], start="start") is not None     # an empty file parses


@pytest.mark.parametrize("text", ["not json", ""])
def test_unreadable_tables_fall_back(tmp_path, monkeypatch, text):
    broken = tmp_path / "tables.json"
    broken.write_text(text, encoding="utf-8")
    monkeypatch.setattr(lalr, "TABLES_PATH", broken)
    assert lalr._read_tables() is None
    assert lalr.load_parser() is not None


def test_grammar_has_no_shift_reduce_conflicts():
    """lark resolves shift/reduce conflicts silently as shifts; strict mode makes them errors, so
    a grammar edit cannot quietly change how existing sources parse."""
    from lark import Lark
    Lark(lalr.grammar_text(), **dict(lalr._options(), strict=True))
