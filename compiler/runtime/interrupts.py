"""Ctrl-C during a run. CasADi polls for signals inside its callbacks and reports an interrupt as
a failed residual evaluation ("IDA_RES_FAIL"); while a run is going, SIGINT also sets `pending`
here, so that the integrator reports it as what it is."""
from __future__ import annotations

import signal
import threading
from contextlib import contextmanager
from typing import Iterator

pending = False


@contextmanager
def watching() -> Iterator[None]:
    global pending
    pending = False
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.getsignal(signal.SIGINT)

    def on_interrupt(signum, frame):
        global pending
        pending = True
        raise KeyboardInterrupt

    signal.signal(signal.SIGINT, on_interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
        pending = False
