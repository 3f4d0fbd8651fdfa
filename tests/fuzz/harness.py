"""Running one fuzzed `dyadc` command and judging its outcome.

In process (fast): `compiler.cli.main(argv)` with stdout/stderr captured, the working directory
set to the example's own temporary folder, a wall-clock alarm and an address-space limit on the
process for the duration of the call. In a subprocess (proof of the bound): the same command in
a fresh interpreter under RLIMIT_AS and a timeout.
"""
from __future__ import annotations

import contextlib
import io
import os
import re
import resource
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

# Per example: a fuzzed command may use this much wall time and this much address space on top of
# what the test process had mapped before it (the subprocess gets MEMORY_LIMIT in total).
TIME_LIMIT_S = 60.0
EXTRA_MEMORY_BYTES = 3 << 30
MEMORY_LIMIT_BYTES = 4 << 30

_LOCATED = re.compile(r"^\S.*:\d+:\d+: error: \S", re.MULTILINE)
_PLAIN = re.compile(r"^error: \S", re.MULTILINE)
_USAGE = re.compile(r"^dyadc( \w+)?: error: ", re.MULTILINE)


class ExampleTimeout(BaseException):
    """Raised by the alarm; a BaseException so that the CLI's `except Exception` cannot swallow it."""


@dataclass
class Outcome:
    argv: list[str]
    status: int | None           # exit status; None when an exception escaped main()
    stdout: str
    stderr: str
    seconds: float
    escaped: BaseException | None = None

    def describe(self) -> str:
        escaped = f"\nescaped: {self.escaped!r}" if self.escaped is not None else ""
        return (f"dyadc {' '.join(map(repr, self.argv))}\nexit {self.status} after {self.seconds:.1f} s"
                f"{escaped}\nstderr:\n{self.stderr[-3000:]}")


def _vm_size() -> int:
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
    return 0


@contextlib.contextmanager
def _bounded(seconds: float, extra_bytes: int):
    """Alarm after `seconds`; at most `extra_bytes` more address space until the block ends."""
    def on_alarm(signum, frame):
        raise ExampleTimeout(f"no outcome after {seconds:g} s")
    previous_handler = signal.signal(signal.SIGALRM, on_alarm)
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    limit = _vm_size() + extra_bytes
    if hard != resource.RLIM_INFINITY:
        limit = min(limit, hard)
    resource.setrlimit(resource.RLIMIT_AS, (limit, hard))
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
        signal.signal(signal.SIGALRM, previous_handler)


def run_in_process(argv: list[str], workdir: Path, seconds: float = TIME_LIMIT_S,
                   extra_bytes: int = EXTRA_MEMORY_BYTES) -> Outcome:
    from compiler.cli import main
    out, err = io.StringIO(), io.StringIO()
    escaped = None
    status = None
    began = time.perf_counter()
    with contextlib.chdir(workdir), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            with _bounded(seconds, extra_bytes):
                status = main(list(argv))
        except SystemExit as exit_:          # argparse: usage errors (2) and --help (0)
            status = exit_.code if isinstance(exit_.code, int) else 1
        except BaseException as exc:        # noqa: BLE001 - anything else escaping main() is the finding
            escaped = exc
    return Outcome(list(argv), status, out.getvalue(), err.getvalue(), time.perf_counter() - began, escaped)


def _limit_child_memory() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT_BYTES, MEMORY_LIMIT_BYTES))


def run_in_subprocess(argv: list[str], workdir: Path, seconds: float = TIME_LIMIT_S) -> Outcome:
    """The command in a fresh interpreter with at most MEMORY_LIMIT_BYTES of address space; a run
    past `seconds` is killed and reported as escaped TimeoutExpired."""
    code = "import sys\nfrom compiler.cli import main\nsys.exit(main(sys.argv[1:]))"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))}
    env.pop("DYADC_DEBUG", None)
    began = time.perf_counter()
    try:
        run = subprocess.run([sys.executable, "-c", code, *argv], cwd=workdir, env=env, capture_output=True,
                             text=True, errors="replace", timeout=seconds, preexec_fn=_limit_child_memory)
    except subprocess.TimeoutExpired as exc:
        return Outcome(list(argv), None, "", str(exc.stderr or ""), time.perf_counter() - began, exc)
    return Outcome(list(argv), run.returncode, run.stdout, run.stderr, time.perf_counter() - began)


def problems(outcome: Outcome, seconds: float = TIME_LIMIT_S) -> list[str]:
    """What is wrong with an outcome; empty when it is a success or a clear error."""
    if isinstance(outcome.escaped, (ExampleTimeout, subprocess.TimeoutExpired)):
        return [f"no outcome within {seconds:g} s"]
    if outcome.escaped is not None:
        return [f"{type(outcome.escaped).__name__} escaped main(): {outcome.escaped}"]
    found = []
    if "internal error:" in outcome.stderr:
        found.append("internal error")
    if "Traceback (most recent call last)" in outcome.stderr:
        found.append("traceback on stderr")
    if outcome.status is not None and outcome.status < 0:
        found.append(f"killed by signal {-outcome.status}")
    if not found and not _clear_exit(outcome):
        found.append(f"exit {outcome.status} without a clear message")
    if outcome.seconds > seconds:
        found.append(f"took {outcome.seconds:.1f} s (limit {seconds:g} s)")
    return found


def _clear_exit(outcome: Outcome) -> bool:
    """Success; an `error:` (located or not) with exit 1; argparse's usage error with exit 2."""
    if outcome.status == 0:
        return True
    if outcome.status == 1:
        return bool(_LOCATED.search(outcome.stderr) or _PLAIN.search(outcome.stderr))
    return outcome.status == 2 and bool(_USAGE.search(outcome.stderr))


def is_located(outcome: Outcome) -> bool:
    return bool(_LOCATED.search(outcome.stderr))
