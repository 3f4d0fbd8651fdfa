"""`dyadc fmt` with the comments kept: the canonical print of compiler/syntax/format.py, and every
`# comment` of the source put back where it was, as black, gofmt and rustfmt do.

The parser drops comments, so they are read from the text (outside strings) and placed by line:
each printed line knows the source lines of the node it prints (format.Line); a keyword line
(`relations`, `end`, `else`, a doc string) is matched to the next source line that starts with
the same word. A whole-line comment goes before the first printed line whose source comes after
it, indented like that line (one step deeper before `end`, `else` or `relations`); a trailing comment
goes at the end of the line printing the innermost node on its source line.
"""
from __future__ import annotations

import re
from dataclasses import dataclass

from compiler.syntax.format import INDENT, format_blocks
from compiler.syntax.parser import parse_source

# The grammar's string terminals (LONG_STRING, STRING) and COMMENT; anything else is skipped.
_SCAN = re.compile(r'"""(?:[^\\]|\\[\s\S])*?"""|"(?:[^"\\\n]|\\.)*"|(#[^\n]*)|[^"#]+|"')
_CLOSERS = ("end", "else", "elseif", "case", "relations", "metadata")   # a comment before one is in the body


@dataclass(frozen=True)
class Comment:
    line: int           # 1-based source line
    text: str           # from `#` to the end of the line, trailing spaces removed
    trailing: bool      # code before it on its line


@dataclass
class _Unit:
    """One printed line (a doc string may span several) and the source lines it prints."""
    text: str
    first: int | None
    last: int | None
    block: int


def comments_of(text: str) -> list[Comment]:
    """Every comment of `text` (never a `#` inside a string), in order."""
    found = []
    for match in _SCAN.finditer(text):
        if match.group(1) is None:
            continue
        start = match.start()
        line_start = text.rfind("\n", 0, start) + 1
        found.append(Comment(text.count("\n", 0, start) + 1, match.group(1).rstrip(),
                             bool(text[line_start:start].strip())))
    return found


def format_source(text: str, filename: str) -> str:
    """The canonical print of the source `text` with its comments in place."""
    blocks = format_blocks(parse_source(text, filename))
    comments = comments_of(text)
    if not comments:
        return "\n\n".join("\n".join(block) for block in blocks) + "\n"
    source = text.splitlines()
    units = _anchored_units(blocks, source, {c.line for c in comments if not c.trailing})
    for comment in (c for c in comments if c.trailing):
        unit = _innermost(units, comment.line)
        unit.text += f"  {comment.text}"
    return _render(units, [c for c in comments if not c.trailing], source, len(blocks))


def _anchored_units(blocks: list[list[str]], source: list[str], comment_lines: set[int]) -> list[_Unit]:
    units = [_Unit(str(line), *_span_lines(line), block=b) for b, block in enumerate(blocks) for line in block]
    cursor = 0
    for index, unit in enumerate(units):
        if unit.first is not None:
            cursor = max(cursor, unit.first)
            continue
        bound = next((u.first for u in units[index + 1:] if u.first is not None), len(source) + 1)
        word = _first_word(unit.text)
        for number in range(cursor + 1, bound):
            if number not in comment_lines and _first_word(source[number - 1]) == word:
                unit.first, unit.last = number, number + unit.text.count("\n")
                cursor = number
                break
    following = None
    for unit in reversed(units):        # a line not found in the source goes with what follows it
        if unit.first is None:
            unit.first = following
        else:
            following = unit.first
    return units


def _span_lines(line) -> tuple[int | None, int | None]:
    span = getattr(line, "span", None)
    return (span.line, span.end_line) if span is not None else (None, None)


def _first_word(text: str) -> str:
    stripped = text.strip()
    if stripped.startswith('"'):
        return '"'
    match = re.match(r"[\w.]+", stripped)
    return match.group(0) if match else stripped[:1]


def _innermost(units: list[_Unit], line: int) -> _Unit:
    """The unit printing the smallest node on source line `line`, else the last one before it."""
    containing = [u for u in units if u.first is not None and u.last is not None and u.first <= line <= u.last]
    if containing:
        return min(containing, key=lambda u: u.last - u.first)
    before = [u for u in units if u.first is not None and u.first <= line]
    return before[-1] if before else units[0]


def _render(units: list[_Unit], comments: list[Comment], source: list[str], block_count: int) -> str:
    blocks: list[list[str]] = [[] for _ in range(max(block_count, 1))]
    pending = list(comments)
    for unit in units:
        group = []
        while pending and unit.first is not None and pending[0].line < unit.first:
            group.append(pending.pop(0))
        if group:
            block = blocks[unit.block]
            at_start = not block
            block += [_indent_before(unit.text) + c.text for c in group]
            after = group[-1].line              # a blank line after a file's header comments stays
            if at_start and after < len(source) and not source[after].strip():
                block.append("")
        blocks[unit.block].append(unit.text)
    blocks[-1] += [c.text for c in pending]     # after the last definition
    return "\n\n".join("\n".join(block) for block in blocks if block) + "\n"


def _indent_before(text: str) -> str:
    indent = text[:len(text) - len(text.lstrip(" "))]
    return indent + INDENT if _first_word(text) in _CLOSERS else indent
