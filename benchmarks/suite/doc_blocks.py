"""A benchmark's table inside a doc page: the block between its two marker comments is replaced
by the new one, so each run rewrites its own table and leaves the prose around it alone."""
from __future__ import annotations

from pathlib import Path


def write_block(doc: Path, block: str, begin: str, end: str, heading: str = "") -> None:
    """`block` (which starts with `begin` and ends with `end`) in place of the marked block of
    `doc`; where the doc has none yet, at its end, under `## heading` if one is given."""
    text = doc.read_text(encoding="utf-8") if doc.exists() else ""
    if begin in text and end in text:
        text = text[:text.index(begin)] + block + text[text.index(end) + len(end):]
    else:
        text = text.rstrip("\n") + "\n\n" + (f"## {heading}\n\n" if heading else "") + block + "\n"
    doc.write_text(text, encoding="utf-8")
