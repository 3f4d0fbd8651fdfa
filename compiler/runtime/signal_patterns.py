"""Signal names as a user asks for them (`--vars`): an exact name first, a pattern only when the
name has `*` (any run of characters, dots included) or `?` (one character); `[` is never a
pattern character, it stays an index (`r[1]`)."""
from __future__ import annotations

import re
from typing import Iterable, Sequence

from .errors import ModelInputError, did_you_mean


def is_pattern(text: str) -> bool:
    return "*" in text or "?" in text


def pattern_regex(pattern: str) -> re.Pattern:
    return re.compile("".join(".*" if c == "*" else "." if c == "?" else re.escape(c) for c in pattern))


def expand_patterns(requested: Iterable[str], available: Sequence[str]) -> list[str]:
    """`requested` with each pattern that is not itself a signal's name replaced by the names it
    matches (in the order of `available`); other names are kept as given, for the caller to check.
    A pattern that matches nothing is a ModelInputError."""
    known = set(available)
    out: list[str] = []
    for text in requested:
        if text in known or not is_pattern(text):
            out.append(text)
            continue
        regex = pattern_regex(text)
        found = [name for name in available if regex.fullmatch(name)]
        if not found:
            raise ModelInputError(f"the pattern '{text}' matches no signal"
                                  + did_you_mean(text.replace("*", "").replace("?", ""), available))
        out += found
    return out


def matching_signals(requested: Iterable[str], available: Sequence[str]) -> list[str]:
    """The signals `requested` names, in the order asked (a pattern's matches in the order of
    `available`), each once; `time` is left out. An unknown name, or a pattern that matches
    nothing, is a ModelInputError."""
    known = set(available)
    chosen: dict[str, None] = {}
    for name in expand_patterns(requested, available):
        if name == "time":
            continue
        if name not in known:
            raise ModelInputError(f"unknown signal '{name}'" + did_you_mean(name, available))
        chosen[name] = None
    return list(chosen)
