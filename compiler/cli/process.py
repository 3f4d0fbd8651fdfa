"""What the `dyadc` process does around a command: numpy's OpenBLAS on one thread, warnings as
`warning: ...` lines, and an exit without Python's teardown once the output is written."""
from __future__ import annotations

import os
import sys

# The variables OpenBLAS reads for its thread count (the first one set wins).
BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS")


def blas_on_one_thread() -> None:
    """Load numpy's OpenBLAS with one thread unless the user chose a count. dyadc's matrices are
    small (CasADi and IDAS solve the large systems) and a sweep runs one process per core, so the
    worker threads only cost start-up time; the results are the same (docs/cache.md, "How fast").
    OpenBLAS reads the variable when it is loaded, so this only acts before numpy is imported."""
    if "numpy" not in sys.modules and not any(name in os.environ for name in BLAS_THREAD_VARIABLES):
        os.environ["OPENBLAS_NUM_THREADS"] = "1"


def warning_line(message, category, filename, lineno, file=None, line=None) -> None:
    """Warnings reach a user of the command line as `warning: ...` lines, not as Python's
    file:line report of where in dyadc they were raised."""
    located = getattr(message, "located", False)      # already `FILE:LINE:COL: warning: ...`
    print(message if located else f"warning: {message}", file=file or sys.stderr)


# The status a shell reports for a process ended by SIGPIPE (128 + 13), as `yes | head` ends.
CLOSED_PIPE_STATUS = 141


def quiet_closed_pipe() -> int:
    """The reader of our output went away (`dyadc inspect M | head`): stop writing, as Unix tools
    do, without a message. Python ignores SIGPIPE, so a write raises BrokenPipeError instead;
    standard output is pointed at the null device so that no later flush (ours or Python's at
    exit) raises it again. Returns the exit status to end with."""
    try:
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, sys.stdout.fileno())
        os.close(null)
    except (OSError, ValueError):       # no file descriptor behind sys.stdout (a test's capture)
        pass
    return CLOSED_PIPE_STATUS


def exit_without_teardown(status: int) -> None:
    """End this process with `status` once its output is written and its atexit handlers ran
    (temporary folders, log handlers, child processes), without Python's teardown, which frees the
    compiler's sympy expressions one by one (docs/cache.md, "How fast"). Nothing is lost: dyadc
    closes every file it writes; the process ends normally instead when a thread besides the main
    one is still running (its work would be cut short) or the output cannot be flushed for another
    reason than a closed pipe (Python's own exit reports it)."""
    import atexit
    import threading
    run_exit_handlers = getattr(atexit, "_run_exitfuncs", None)
    if run_exit_handlers is None or threading.active_count() != 1:
        return
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except BrokenPipeError:
        status = quiet_closed_pipe()
    except (OSError, ValueError):
        return
    run_exit_handlers()
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except (OSError, ValueError):
        pass
    os._exit(status)
