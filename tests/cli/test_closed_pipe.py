"""`dyadc inspect MODEL | head`: a reader that goes away ends dyadc quietly, as it ends Unix
tools: no message, the status a shell reports for SIGPIPE (141), never "internal error"."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from compiler.cli.process import CLOSED_PIPE_STATUS

MODEL = """component Decay
  variable x::Real
relations
  initial x = 1
  der(x) = -x
end
"""


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX pipes")
@pytest.mark.parametrize("command", ["parse", "inspect"])
def test_output_to_a_pipe_nobody_reads_ends_quietly(tmp_path, command):
    model = tmp_path / "Decay.dyad"
    model.write_text(MODEL, encoding="utf-8")
    read_end, write_end = os.pipe()
    os.close(read_end)                         # the reader is gone before dyadc writes a byte
    try:
        finished = subprocess.run(
            [sys.executable, "-m", "compiler", command, str(model)], stdout=write_end,
            stderr=subprocess.PIPE, text=True, cwd=tmp_path, timeout=120,
            env={**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[2])})
    finally:
        os.close(write_end)
    assert (finished.returncode, finished.stderr) == (CLOSED_PIPE_STATUS, "")
