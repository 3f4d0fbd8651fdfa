"""A one-line progress bar on stderr. It only reads where the run is: the run is cut into the same
segments whether or not a bar is shown, so showing it never changes a number."""
from __future__ import annotations

import sys
import time as _time

PROGRESS_DELAY = 2.0        # seconds of run time before the bar appears


class Progress:
    def __init__(self, enabled: bool, start: float, stop: float, after: float | None = None):
        self.enabled = enabled
        self.start, self.stop = start, stop
        self.after = PROGRESS_DELAY if after is None else after
        self.began = _time.perf_counter()
        self.shown = False

    def update(self, t: float) -> None:
        if not self.enabled:
            return
        elapsed = _time.perf_counter() - self.began
        if elapsed < self.after and not self.shown:
            return
        self.shown = True
        span = self.stop - self.start
        fraction = 1.0 if span == 0 else min(max((t - self.start) / span, 0.0), 1.0)
        width = 30
        bar = "#" * int(round(fraction * width))
        sys.stderr.write(f"\r[{bar:<{width}}] t = {t:.4g} / {self.stop:.4g}  {elapsed:6.1f} s")
        sys.stderr.flush()

    def close(self) -> None:
        if self.shown:
            sys.stderr.write("\n")
            sys.stderr.flush()
