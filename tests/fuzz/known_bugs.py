"""Bugs the fuzzer found and that are not fixed yet: how to recognize an input that triggers one.

The fuzz tests skip (hypothesis `assume`) inputs that match an entry here, so that `make test`
stays green while each bug stays recorded by its strict-xfail reproducer in
test_fuzz_known_bugs.py. Fixing a bug makes its reproducer pass, which fails the suite (strict
xfail) until the entry here and the xfail mark are removed: the fuzzer then covers it again.

Fixed and removed from here (their reproducers are plain tests in test_fuzz_known_bugs.py): names
over 255 bytes, a NUL byte in an argument, the power tower `9^9^9`, sizes of 1e9 and 1e308,
`dyadc linearize` of a mass of 1e-400. A new entry's reproducer is marked
`pytest.mark.xfail(strict=True, reason=...)`.
"""
from __future__ import annotations

# name -> a test of (argv, model text) that is true for inputs triggering that bug
# (none open: the last, `dyadc linearize` of a mass that underflows to 0, was fixed 2026-11-28)
_KNOWN: dict[str, object] = {}


def known_bug(argv: list[str], text: str = "") -> str | None:
    """The name of the known bug this input triggers, or None."""
    for name, triggers in _KNOWN.items():
        if triggers(argv, text):
            return name
    return None
