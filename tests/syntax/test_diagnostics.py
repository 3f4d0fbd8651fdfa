"""Every file in broken/ starts with `# expect LINE:COL: message` and must fail exactly there."""
import re
from pathlib import Path

import pytest

from compiler.errors import DyadError
from compiler.syntax.parser import parse_file, parse_source

BROKEN = sorted((Path(__file__).parent / "broken").glob("*.dyad"))
EXPECT = re.compile(r"# expect (\d+):(\d+): (.+)")


def test_corpus_is_large_enough():
    assert len(BROKEN) >= 30


@pytest.mark.parametrize("path", BROKEN, ids=lambda p: p.stem)
def test_broken_source_reports_located_message(path):
    line, column, message = EXPECT.match(path.read_text(encoding="utf-8")).groups()
    with pytest.raises(DyadError) as caught:
        parse_file(path)
    err = caught.value
    assert (err.span.line, err.span.column) == (int(line), int(column)), err.format()
    assert err.span.file == str(path)
    assert message in err.message
    rendered = err.format()
    assert rendered.startswith(f"{path}:{line}:{column}: error: ")
    assert "^" in rendered          # the caret line shows the source


def test_missing_end_names_the_block_and_where_it_opened():
    with pytest.raises(DyadError) as caught:
        parse_source("\n\ncomponent Foo\n  parameter x::Real = 1\n", "f.dyad")
    assert caught.value.message == ("expected `end` to close component `Foo` (opened at 3:1), "
                                    "found end of file")
    assert caught.value.notes[0].span.line == 3


def test_duplicate_declaration_points_at_both():
    src = "component Foo\n  parameter x::Real = 1\n  variable x::Real\nend\n"
    with pytest.raises(DyadError) as caught:
        parse_source(src, "d.dyad")
    assert caught.value.span.line == 3
    assert caught.value.notes[0].span.line == 2


def test_der_of_subcomponent_parameter_is_not_flagged_at_parse_time():
    # `der(body.m)` needs the library to know whether `m` is a parameter.
    src = "component Foo\n  body = Body()\n  variable x::Real\nrelations\n  x = der(body.m)\nend\n"
    parse_source(src, "ok.dyad")


def test_der_of_variable_is_accepted():
    src = "component Foo\n  variable x::Real\nrelations\n  der(x) = -x\nend\n"
    parse_source(src, "ok.dyad")
