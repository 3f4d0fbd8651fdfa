"""`dyadc fmt` keeps every comment, whole-line and trailing, where it was (issue 28): on every file
of components/ (the comments, in order and of the same kind; the same AST; idempotent) and on a
file with comments in every kind of place (the exact output)."""
from pathlib import Path

import pytest

from compiler.cli import main
from compiler.syntax.format_comments import comments_of, format_source
from compiler.syntax.parser import parse_source

REPO = Path(__file__).resolve().parents[2]
LIBRARY = sorted(REPO.glob("components/**/*.dyad"))


def test_the_library_has_comments_to_keep():
    assert sum(len(comments_of(p.read_text(encoding="utf-8"))) for p in LIBRARY) >= 30


@pytest.mark.parametrize("path", LIBRARY, ids=lambda p: str(p.relative_to(REPO)))
def test_every_comment_of_the_library_survives_formatting(path):
    text = path.read_text(encoding="utf-8")
    printed = format_source(text, str(path))
    assert [(c.text, c.trailing) for c in comments_of(printed)] == \
        [(c.text, c.trailing) for c in comments_of(text)]
    assert parse_source(printed, "printed") == parse_source(text, "original")
    assert format_source(printed, "again") == printed


# The formatted file, with comments in every kind of place ...
EXPECTED = '''\
# Header of the file.
# Second line.

"A thing"
component Thing  # the component
  # the parameters
  "Gain"
  parameter k::Real = 2  # dimensionless
  variable x::Real
  # before relations
relations
  # the dynamics
  der(x) = -k * x  # decay
  if x > 1  # large
    # inside the if
    y = 1
  else
    y = 0  # small
    # last in else
  end
  # last in the component
end
# after everything
'''

# ... and its lines as a person types them: only the spacing differs (what the formatter mends),
# every comment is where it was.
AS_TYPED = [("component Thing  # the component", "component Thing   # the component"),
            ("parameter k::Real = 2  # dimensionless", "parameter k::Real=2    # dimensionless"),
            ("der(x) = -k * x  # decay", "der(x) = -k*x   # decay"),
            ("if x > 1  # large", "if x > 1   # large"),
            ("y = 0  # small", "y = 0 # small")]


def as_typed(formatted: str) -> str:
    for line, typed in AS_TYPED:
        assert formatted.count(line) == 1, line
        formatted = formatted.replace(line, typed)
    return formatted


MESSY = as_typed(EXPECTED)


def test_comments_in_every_kind_of_place_stay_where_they_were():
    assert format_source(MESSY, "messy.dyad") == EXPECTED
    assert format_source(EXPECTED, "again.dyad") == EXPECTED


def test_fmt_write_keeps_the_comments(tmp_path, capsys):
    path = tmp_path / "Thing.dyad"
    path.write_text(MESSY, encoding="utf-8")
    assert main(["fmt", str(path)]) == 0
    assert capsys.readouterr().out == EXPECTED
    assert main(["fmt", "-w", str(path)]) == 0
    assert path.read_text(encoding="utf-8") == EXPECTED
