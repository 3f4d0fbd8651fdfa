"""Ctrl-C during a sweep is taken between samples, never inside one: a KeyboardInterrupt raised in
the middle of a solver call could be swallowed by native code (and turned into a failed sample).
SIGINT only sets a flag; the sweep checks it after each sample and while it waits for workers.
A second Ctrl-C interrupts at once."""
from __future__ import annotations

import signal
import threading


class DeferredInterrupt:
    def __init__(self):
        self.requested = False
        self._previous = None
        self._installed = False

    def __enter__(self) -> "DeferredInterrupt":
        if threading.current_thread() is threading.main_thread():
            self._previous = signal.signal(signal.SIGINT, self._handle)
            self._installed = True
        return self

    def __exit__(self, *exc) -> None:
        if self._installed:
            signal.signal(signal.SIGINT, self._previous)
            self._installed = False

    def _handle(self, signum, frame) -> None:
        if self.requested:
            raise KeyboardInterrupt
        self.requested = True

    def check(self) -> None:
        if self.requested:
            raise KeyboardInterrupt
