"""Ctrl-C during a run: `interrupted at t = ...`, exit status 130, no output file (issue 19.7)."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

SLOW = """component Forced
  variable x::Real
  variable y::Real
relations
  initial x = 1
  initial y = 0
  der(x) = y
  der(y) = -x + sin(1000 * time)
end
"""

@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_ctrl_c_during_the_solve_reports_the_time_and_exits_130(tmp_path):
    model = tmp_path / "Forced.dyad"
    model.write_text(SLOW, encoding="utf-8")
    output = tmp_path / "out.csv"
    process = subprocess.Popen(
        [sys.executable, "-m", "compiler", "simulate", str(model), "--stop", "1000", "--rtol", "1e-10",
         "--atol", "1e-12", "--points", "1001", "--output", str(output)],
        cwd=tmp_path, stderr=subprocess.PIPE, text=True,
        env={**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[2])})
    time.sleep(6.0)                                     # compiled by now, deep in the solve
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=30)
    assert process.returncode == 130, err
    assert "interrupted" in err and "Traceback" not in err and "internal error" not in err
    assert not output.exists()
    assert [p.name for p in tmp_path.iterdir()] == ["Forced.dyad"]
