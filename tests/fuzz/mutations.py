"""Token-level mutations of Dyad source text and of command lines.

The tokenizer is our own rough one (not the compiler's): a mutation needs token boundaries, not
meaning, and the fuzzer must not depend on the compiler's internal modules.
"""
from __future__ import annotations

import re
from dataclasses import dataclass

from tests.fuzz.seeds import nested

_TOKEN = re.compile(r'"""(?:.|\n)*?"""|"(?:[^"\\\n]|\\.)*"|#[^\n]*'
                    r"|\d+\.?\d*(?:[eE][+-]?\d+)?[a-zA-Zμ]?|\.\d+(?:[eE][+-]?\d+)?"
                    r"|[^\W\d]\w*|::|<=|>=|==|!=|\S", re.UNICODE)
_IDENTIFIER = re.compile(r"[^\W\d]\w*\Z", re.UNICODE)
_NUMBER = re.compile(r"[\d.]")
_KEYWORDS = frozenset("component connector partial extends relations end parameter variable initial "
                      "for in if then else elseif connect der time Real Integer sin".split())


@dataclass(frozen=True)
class Token:
    start: int
    end: int
    text: str


def tokenize(text: str) -> list[Token]:
    return [Token(m.start(), m.end(), m.group()) for m in _TOKEN.finditer(text)
            if not m.group().startswith("#")]


def _pick(tokens: list[Token], index: int, keep=lambda t: True) -> Token | None:
    chosen = [t for t in tokens if keep(t)]
    return chosen[index % len(chosen)] if chosen else None


def _replace(text: str, token: Token, new: str) -> str:
    return text[:token.start] + new + text[token.end:]


def mutate_source(text: str, operation: str, i: int, j: int, payload: str = "") -> str:
    """One mutation of `text`; `i`, `j` pick tokens (modulo their count), `payload` is what an
    operation inserts: an extreme number, a hostile name or a nesting kind and depth."""
    tokens = tokenize(text)
    a = _pick(tokens, i)
    if a is None:
        return text
    if operation == "delete":
        return _replace(text, a, "")
    if operation == "duplicate":
        return text[:a.end] + " " + a.text + text[a.end:]
    if operation == "swap":
        b = _pick(tokens, j)
        first, second = sorted((a, b), key=lambda t: t.start)
        if first.end > second.start:
            return text
        return (text[:first.start] + second.text + text[first.end:second.start] + first.text
                + text[second.end:])
    if operation == "number":
        target = _pick(tokens, i, lambda t: bool(_NUMBER.match(t.text)))
        return text if target is None else _replace(text, target, payload)
    if operation == "rename":            # every occurrence of one identifier (declaration and uses)
        target = _pick(tokens, i, lambda t: bool(_IDENTIFIER.match(t.text)) and t.text not in _KEYWORDS)
        if target is None:
            return text
        return re.sub(rf"(?<![\w.]){re.escape(target.text)}(?!\w)", lambda m: payload, text)
    if operation == "nest":              # an operand becomes a deeply nested expression
        kind, depth = payload.split(":")
        target = _pick(tokens, i, lambda t: bool(_NUMBER.match(t.text) or _IDENTIFIER.match(t.text))
                       and t.text not in _KEYWORDS)
        return text if target is None else _replace(text, target, nested(kind, int(depth), target.text))
    if operation == "string":            # a docstring or string literal gets hostile content
        target = _pick(tokens, i, lambda t: t.text.startswith('"'))
        return text if target is None else _replace(text, target, '"' + payload + '"')
    raise ValueError(f"unknown mutation {operation}")


SOURCE_OPERATIONS = ("delete", "duplicate", "swap", "number", "rename", "nest", "string")


def mutate_argv(argv: list[str], operation: str, i: int, j: int, payload: str = "") -> list[str]:
    """One mutation of a command line: delete, duplicate, swap or replace an argument, or insert
    a hostile one."""
    if not argv:
        return [payload]
    argv = list(argv)
    k = i % len(argv)
    if operation == "delete":
        del argv[k]
    elif operation == "duplicate":
        argv.insert(k, argv[k])
    elif operation == "swap":
        m = j % len(argv)
        argv[k], argv[m] = argv[m], argv[k]
    elif operation == "replace":
        argv[k] = payload
    elif operation == "insert":
        argv.insert(k, payload)
    else:
        raise ValueError(f"unknown mutation {operation}")
    return argv


ARGV_OPERATIONS = ("delete", "duplicate", "swap", "replace", "insert")
