"""`enum Name =` followed by one `| Member` per line, as Dyad's documentation writes its library
enums (help.juliahub.com, FluidComponents `Types.CvTypes`): a line that starts with `|` continues
the declaration (compiler/syntax/layout.py). The three spellings of one enum parse alike and
`dyadc fmt` prints them back as one line that parses the same."""
from __future__ import annotations

import pytest

from compiler.errors import DyadError
from compiler.syntax.format import format_file
from compiler.syntax.parser import parse_source

ONE_LINE = "enum Valve = Kv | Cv(scale::Real = 2) | OpPoint\n"
ONE_PER_LINE = "enum Valve =\n  | Kv\n  | Cv(scale::Real = 2)\n  | OpPoint\n"
BLOCK = "enum Valve\n  | Kv\n  | Cv(scale::Real = 2)\n  OpPoint\nend\n"


def members(text: str) -> list[tuple[str, tuple]]:
    (definition,) = parse_source(text, "t.dyad").definitions
    return list(zip(definition.members, definition.fields or ((),) * len(definition.members)))


@pytest.mark.parametrize("text", [ONE_PER_LINE, BLOCK])
def test_every_spelling_declares_the_same_members(text):
    assert members(text) == members(ONE_LINE)
    assert [name for name, _ in members(text)] == ["Kv", "Cv", "OpPoint"]


def test_fmt_round_trips_the_one_per_line_form():
    parsed = parse_source(ONE_PER_LINE + "\ncomponent C\nend\n", "t.dyad")
    assert parse_source(format_file(parsed), "fmt.dyad") == parsed
    assert members(format_file(parse_source(ONE_PER_LINE, "t.dyad"))) == members(ONE_LINE)


def test_a_declaration_after_the_enum_is_not_a_member():
    file = parse_source(ONE_PER_LINE + "component C\nend\n", "t.dyad")
    assert [d.name for d in file.definitions] == ["Valve", "C"]


def test_a_member_line_without_its_bar_is_located():
    with pytest.raises(DyadError) as info:
        parse_source("enum Valve =\n  | Kv\n  Cv\n", "t.dyad")
    assert (info.value.span.line, info.value.span.column) == (3, 3)
