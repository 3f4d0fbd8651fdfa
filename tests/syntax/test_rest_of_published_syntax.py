"""The rest of the published syntax (issue 27, item 3): `using` in Julia's forms, `time` as a
declared name, `path` declarations, `switch` everywhere, filtered and nested comprehensions,
`enum` in every position. What each form parses into and the located errors around them;
examples written for these tests from Dyad's documentation, not copied."""
import pytest

from compiler.errors import DyadError
from compiler.syntax import ast
from compiler.syntax.format import format_file
from compiler.syntax.parser import parse_source


def parse(text: str) -> ast.File:
    result = parse_source(text, "t.dyad")
    assert parse_source(format_file(result), "t.dyad<fmt>") == result     # fmt round-trips
    return result


def error(text: str) -> DyadError:
    with pytest.raises(DyadError) as caught:
        parse_source(text, "t.dyad")
    assert caught.value.span is not None and caught.value.span.file == "t.dyad"
    return caught.value


# ------------------------------------------------------------------------------------- using

def test_using_forms_absolute_relative_and_several_on_a_line():
    usings = parse("using Gears\nusing Gears.Spur, .Local\nusing ..Sibling.Deep: Shaft, Hub\n"
                   "component C\nend\n").usings
    assert [(u.level, u.package, u.names) for u in usings] == [
        (0, "Gears", ()), (0, "Gears.Spur", ()), (1, "Local", ()),
        (2, "Sibling.Deep", ("Shaft", "Hub"))]
    assert [u.written for u in usings] == ["Gears", "Gears.Spur", ".Local", "..Sibling.Deep"]


@pytest.mark.parametrize("written, within, absolute", [
    ("using .Sub", "Pkg.Inner", "Pkg.Inner.Sub"),
    ("using ..Sibling", "Pkg.Inner", "Pkg.Sibling"),
    ("using ..Other", "Pkg", "Other"),
    ("using Plain", "Pkg.Inner", "Plain"),
])
def test_a_relative_using_counts_its_dots_from_the_files_package(written, within, absolute):
    (using,) = parse(written + "\n").usings
    assert using.absolute_package(within) == absolute


def test_a_relative_using_above_the_top_level_is_a_located_error():
    (using,) = parse("\n  using ...Far: x\n").usings
    with pytest.raises(DyadError) as caught:
        using.absolute_package("Pkg")
    err = caught.value
    assert (err.span.line, err.span.column) == (2, 3)
    assert "above the top-level packages" in err.message and err.hint == "name the package absolutely: `using Far`"
