"""Two Julia spellings rewritten into the Dyad expressions they mean, before a Julia function's
body is parsed (compiler/julia/source.py):

- the broadcast macro `@. expr`: every operator of `expr` applies element by element
  (`@. r^2 + 1` is `r .^ 2 .+ 1`);
- an operator called like a function, `^(r, 2)` or `+(a, b, c)`: the operator between its
  arguments (`(r) ^ (2)`).

Only text outside string literals is touched; nothing is evaluated.
"""
from __future__ import annotations

import re

_OPERATORS = "+-*/^"
_BROADCAST = re.compile(r"^\s*@\.\s+")
# an operator directly followed by `(` where an operand cannot precede it: a call of the operator
_OPERATOR_CALL = re.compile(r"(?:(?<=^)|(?<=[(\[,=\s]))([-+*/^])\(")


def translate(source: str) -> str:
    broadcast = _BROADCAST.match(source)
    body = source[broadcast.end():] if broadcast else source
    body = _operator_calls(body)
    return " " * (broadcast.end() if broadcast else 0) + (_dotted(body) if broadcast else body)


def _operator_calls(text: str) -> str:
    searched = 0
    while True:
        found = next((m for m in _OPERATOR_CALL.finditer(text, searched)
                      if not _in_string(text, m.start())), None)
        if found is None:
            return text
        operator, open_at = found[1], found.end() - 1
        close_at, arguments = _arguments(text, open_at)
        searched = found.end()
        if close_at is None or len(arguments) < 2:
            continue                          # unary `-(x)` or unbalanced: leave it to the parser
        joined = f" {operator} ".join(f"({argument.strip()})" for argument in arguments)
        text = f"{text[:found.start()]}({joined}){text[close_at + 1:]}"


def _arguments(text: str, open_at: int) -> tuple[int | None, list[str]]:
    depth, start, parts = 0, open_at + 1, []
    for position in range(open_at, len(text)):
        char = text[position]
        if char in "([{":
            depth += 1
        elif char in ")]}":
            depth -= 1
            if depth == 0:
                parts.append(text[start:position])
                return position, parts
        elif char == "," and depth == 1:
            parts.append(text[start:position])
            start = position + 1
    return None, []


def _dotted(text: str) -> str:
    out, index = [], 0
    while index < len(text):
        char = text[index]
        previous = text[index - 1] if index else ""
        if char == '"':
            end = text.find('"', index + 1)
            end = len(text) - 1 if end < 0 else end
            out.append(text[index:end + 1])
            index = end + 1
            continue
        if char in _OPERATORS and previous != "." and not _exponent_sign(text, index) \
                and not _unary(text, index):
            out.append("." + char)
        else:
            out.append(char)
        index += 1
    return "".join(out)


def _exponent_sign(text: str, index: int) -> bool:
    """The sign in `1e-3` belongs to the number."""
    return text[index] in "+-" and index >= 2 and text[index - 1] in "eE" \
        and text[index - 2].isdigit()


def _unary(text: str, index: int) -> bool:
    """A sign with no operand before it (`-x`, `(-x)`, `a * -x`) stays as it is."""
    before = text[:index].rstrip()
    return text[index] in "+-" and (not before or before[-1] in "([,=" + _OPERATORS)


def _in_string(text: str, position: int) -> bool:
    return text.count('"', 0, position) % 2 == 1
