"""`dyadc sweep` from the command line: without Dask, bad requests, and Ctrl-C (serial and on a
local cluster) keeping the finished samples in a file named as partial."""
import math
import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from compiler import cli
from tests.sweep.models import write_decay

ROOT = Path(__file__).resolve().parents[2]
DYADC = str(Path(sys.executable).parent / "dyadc")


def test_without_dask_a_plain_sweep_says_how_to_install_it_and_serial_still_works(tmp_path, monkeypatch, capsys):
    model = write_decay(tmp_path)
    monkeypatch.setitem(sys.modules, "distributed", None)         # as if the extra were not installed
    code = cli.main(["sweep", str(model), "--stop", "1", "-p", "k=[1,2]"])
    err = capsys.readouterr().err
    assert code == 1
    assert "runs its samples on Dask (dask.distributed), which is not installed" in err
    assert "pip install 'dyadc[sweep]'" in err and "--serial" in err and "Traceback" not in err
    code = cli.main(["sweep", str(model), "--stop", "1", "--points", "5", "-p", "k=[1,2]", "--serial",
                     "--metrics", "final(x)", "--output", str(tmp_path / "s.csv")])
    assert code == 0
    assert (tmp_path / "s.csv").read_text().splitlines()[0] == "sample,k,time,x"
    assert (tmp_path / "s.samples.csv").exists()


@pytest.mark.parametrize("args, says", [
    (["-p", "k=1:2"], "needs --samples"),
    (["-p", "k=[1,2]", "--output", "out.txt"], "name the output FILE.parquet or FILE.csv"),
    (["-p", "k=[1,2]", "--seed", "3"], "--seed only applies to --samples"),
    (["-p", "k=[1,2]", "--metrics", "max(x"], "<metric 1>:1:6: error: missing `)`"),
    (["-p", "n=[1,2]"], "`n` is a structural parameter"),
    (["-p", "k=[1,2]", "--scheduler", "tcp://127.0.0.1:1"], "--serial runs here without Dask"),
])
def test_bad_requests_are_clear_errors(tmp_path, capsys, args, says):
    model = write_decay(tmp_path)
    code = cli.main(["sweep", str(model), "--stop", "1", "--serial", *args])
    err = capsys.readouterr().err
    assert code == 1 and says in err and "Traceback" not in err


def test_samples_from_the_command_line_are_seeded(tmp_path, capsys):
    model = write_decay(tmp_path)
    outputs = []
    for seed in (5, 5, 6):
        assert cli.main(["sweep", str(model), "--stop", "1", "--points", "3", "--serial", "--samples", "6",
                         "--seed", str(seed), "-p", "k=0.5:2", "-p", "x0=[1,2]", "--metrics", "final(x)"]) == 0
        outputs.append(capsys.readouterr().out)
    assert outputs[0] == outputs[1] != outputs[2]
    assert len(outputs[0].splitlines()) == 7 and "final(x)" in outputs[0].splitlines()[0]


def _interrupt_after(process, done_at_least: int, group: bool) -> str:
    """Read the progress bar until `done_at_least` samples are done, then press Ctrl-C."""
    seen = []

    def read():
        for chunk in iter(lambda: process.stderr.read(1), ""):
            seen.append(chunk)

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    deadline = time.monotonic() + 240
    while time.monotonic() < deadline and process.poll() is None:
        counts = [int(n) for n in re.findall(r"\] (\d+)/\d+ samples", "".join(seen))]
        if counts and counts[-1] >= done_at_least:
            (os.killpg if group else os.kill)(process.pid, signal.SIGINT)
            break
        time.sleep(0.05)
    process.wait(timeout=120)
    reader.join(timeout=10)
    return "".join(seen)


@pytest.mark.parametrize("engine", [["--serial"], ["--workers", "2", "--batch-size", "1"]],
                         ids=["serial", "local-cluster"])
def test_ctrl_c_keeps_the_finished_samples_in_a_partial_file(tmp_path, engine):
    pq = pytest.importorskip("pyarrow.parquet")
    if "--workers" in engine:
        pytest.importorskip("distributed")
    model = write_decay(tmp_path)
    out = tmp_path / "sweep.parquet"
    process = subprocess.Popen(
        [DYADC, "sweep", str(model), "--stop", "20", "--points", "2001", "-p", "k=0.5:4:3000", "-p", "c=0.5",
         "--metrics", "final(x)", "--progress", "--output", str(out), *engine],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, cwd=tmp_path,
        start_new_session=True)                       # its own process group, as a terminal job
    try:
        err = _interrupt_after(process, 3, group=True)
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
    assert process.returncode == 130, err
    assert "interrupted: sweep interrupted after" in err and "Traceback" not in err
    assert not out.exists()
    samples = pq.read_table(tmp_path / "sweep.partial.samples.parquet").to_pydict()
    trajectories = pq.read_table(tmp_path / "sweep.partial.parquet").to_pydict()
    done = len(samples["sample"])
    assert 3 <= done < 3000 and set(samples["status"]) == {"ok"}
    assert all(math.isfinite(v) for v in samples["final(x)"])     # the metrics of what finished
    assert len(trajectories["time"]) == 2001 * done
    assert f"the {done} finished samples are in" in err
    deadline = time.monotonic() + 60                  # nothing of the sweep is left running
    while time.monotonic() < deadline:
        try:
            os.killpg(process.pid, 0)
        except ProcessLookupError:
            break
        time.sleep(0.2)
    else:
        pytest.fail("processes of the interrupted sweep are still running a minute later")
