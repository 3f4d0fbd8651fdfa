"""Located diagnostics: every user-facing error names FILE:LINE:COL and shows the source line."""
from __future__ import annotations

import difflib
from dataclasses import dataclass, field
import os
from pathlib import Path

# Sources parsed from memory (tests, stdin) have no file to re-read for the caret line.
_SOURCE_TEXTS: dict[str, str] = {}


def register_source(filename: str, text: str) -> None:
    _SOURCE_TEXTS[filename] = text


def source_line(filename: str, line: int) -> str | None:
    text = _SOURCE_TEXTS.get(filename)
    if text is None:
        try:
            text = Path(filename).read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError):
            return None
        _SOURCE_TEXTS[filename] = text
    lines = text.splitlines()
    if 1 <= line <= len(lines):
        return lines[line - 1]
    return None


def display_path(path: str) -> str:
    """A path as a user wants to read it: relative to the working directory when inside it."""
    if path.startswith("<") or not os.path.isabs(path):
        return path
    try:
        relative = os.path.relpath(path)
    except ValueError:
        return path
    return path if relative.startswith("..") else relative


@dataclass(frozen=True)
class Span:
    """A region of a source file; lines and columns are 1-based, end is inclusive of the last char."""

    file: str
    line: int
    column: int
    end_line: int
    end_column: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}"


@dataclass
class Note:
    message: str
    span: Span | None = None


class DyadError(Exception):
    """The one exception type users see. `format()` renders it the compiler way."""

    def __init__(self, message: str, span: Span | None = None, hint: str | None = None,
                 notes: list[Note] | tuple[Note, ...] = ()):
        super().__init__(message)
        self.message = message
        self.span = span
        self.hint = hint
        self.notes = list(notes)

    def format(self) -> str:
        out = [_render("error", self.message, self.span)]
        for note in self.notes:
            out.append(_render("note", note.message, note.span))
        if self.hint:
            out.append(f"hint: {self.hint}")
        return "\n".join(out)

    def __str__(self) -> str:
        return self.format()


class SimulationError(DyadError):
    """A solver failure: says the time reached and the solver's reason."""

    def __init__(self, message: str, time_reached: float | None = None, reason: str | None = None,
                 hint: str | None = None):
        super().__init__(message, None, hint)
        self.time_reached = time_reached
        self.reason = reason
        self.partial = None          # runtime.Result up to the failure, when there is one


def _render(kind: str, message: str, span: Span | None) -> str:
    if span is None:
        return f"{kind}: {message}"
    head = f"{span.file}:{span.line}:{span.column}: {kind}: {message}"
    text = source_line(span.file, span.line)
    if text is None:
        return head
    width = 1
    if span.end_line == span.line and span.end_column >= span.column:
        width = span.end_column - span.column + 1
    width = max(1, min(width, len(text) - span.column + 1 if len(text) >= span.column else 1))
    caret = " " * (span.column - 1) + "^" + "~" * (width - 1)
    return f"{head}\n    {text}\n    {caret}"


def closest(name: str, candidates, n: int = 1, cutoff: float = 0.6) -> list[str]:
    """The candidates closest to a misspelt `name`, best first (the compile side's one matcher;
    the runtime, which imports nothing of the compiler, has runtime.did_you_mean)."""
    return difflib.get_close_matches(name, sorted(set(candidates)), n=n, cutoff=cutoff)


def suggest_name(name: str, candidates) -> str | None:
    """A hint such as "did you mean `mass`?", or None when nothing is close."""
    match = closest(name, candidates)
    return f"did you mean `{match[0]}`?" if match else None
