"""Bugs the fuzzer found and that are not fixed yet: how to recognize an input that triggers one.

The fuzz tests skip (hypothesis `assume`) inputs that match an entry here, so that `make test`
stays green while each bug stays recorded by its strict-xfail reproducer in
test_fuzz_known_bugs.py. Fixing a bug makes its reproducer pass, which fails the suite (strict
xfail) until the entry here and the xfail mark are removed: the fuzzer then covers it again.
"""
from __future__ import annotations

import os
import re

# A tower of numeric literals, `2^2^2`: sympy evaluates it exactly and does not come back.
_POWER_TOWER = re.compile(r"(\d[\w.]*\s*\^\s*){2,}\d")
# An integer of 7+ digits next to `[`, `]` or `:`: an array size, range or index of millions.
_HUGE_SIZE = re.compile(r"[\[:]\s*\d{7,}|\d{7,}\s*[\]:]")
# A size written with an exponent, `Real[1e308]`.
_EXPONENT_SIZE = re.compile(r"\[\s*[-+]?[\d.]+[eE]")
# A component declared, extended or instantiated under a name too long for a file name.
_LONG_COMPONENT = re.compile(r"\b(?:component|extends)\s+[\w.]*\w{256}|\w{256}\s*\(")


def _option(argv: list[str], name: str, default: str | None = None) -> str | None:
    value = default
    for k, arg in enumerate(argv[:-1]):
        if arg == name:
            value = argv[k + 1]
    return value


def _float(text: str | None) -> float | None:
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def _name_too_long(argv: list[str]) -> bool:
    return any(len(os.fsencode(part)) > 255 for arg in argv for part in re.split(r"[/:.]", arg))


def known_bug(argv: list[str], text: str = "") -> str | None:
    """The name of the known bug this input triggers, or None."""
    if any("\x00" in arg for arg in argv):
        return "nul-in-argument"
    if _name_too_long(argv) or _LONG_COMPONENT.search(text):
        return "name-too-long"
    if _POWER_TOWER.search(text):
        return "power-tower-hangs"
    if _EXPONENT_SIZE.search(text):
        return "exponent-size"
    if _HUGE_SIZE.search(text):
        return "huge-size"
    return None
