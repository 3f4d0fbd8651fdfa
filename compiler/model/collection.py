"""Fewer garbage collections while the compiler builds its symbolic objects.

Flattening and the structure passes allocate hundreds of thousands of long-lived sympy nodes.
With Python's default thresholds (a young collection every 700 allocations, older generations
every 10 of those) the collector re-scans that growing heap again and again, finding almost
nothing (docs/scaling.md). Inside `fewer_collections()` a young collection runs every 50,000
allocations instead; cycles are still collected, only less often. Nested and concurrent uses
raise the threshold once and restore the caller's setting when the last one leaves.
"""
from __future__ import annotations

import gc
import threading
from contextlib import contextmanager

YOUNG_THRESHOLD = 50_000
_lock = threading.Lock()
_depth = 0
_saved: tuple[int, ...] = ()


@contextmanager
def fewer_collections():
    global _depth, _saved
    with _lock:
        if _depth == 0:
            _saved = gc.get_threshold()
            if _saved[0]:                      # 0 means collection is off: leave it off
                gc.set_threshold(max(_saved[0], YOUNG_THRESHOLD), *_saved[1:])
        _depth += 1
    try:
        yield
    finally:
        with _lock:
            _depth -= 1
            if _depth == 0:
                gc.set_threshold(*_saved)
