"""What SUNDIALS writes to file descriptor 2 during an IDAS call becomes part of our error message
(compiler/runtime/idas.py CapturedStderr). The temporary file is reused between captures: each
capture must see only its own text, a capture inside a capture included."""
from __future__ import annotations

import os
import sys

from compiler.runtime.idas import CapturedStderr


def test_each_capture_sees_only_its_own_text():
    texts = []
    for word in ("first message\n", "second\n", ""):
        with CapturedStderr() as captured:
            os.write(2, word.encode())
        texts.append(captured.text)
    assert texts == ["first message\n", "second\n", ""]


def test_a_capture_inside_a_capture_keeps_both_apart():
    with CapturedStderr() as outer:
        os.write(2, b"outer before\n")
        with CapturedStderr() as inner:
            os.write(2, b"inner\n")
        os.write(2, b"outer after\n")
    assert inner.text == "inner\n"
    assert outer.text == "outer before\nouter after\n"


def test_python_level_stderr_is_captured_and_restored():
    before = sys.stderr
    with CapturedStderr() as captured:
        print("through sys.stderr", file=sys.stderr)
    assert sys.stderr is before
    assert "through sys.stderr" in captured.text
