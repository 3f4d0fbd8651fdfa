"""`dyadc sweep --progress`: one progress line for a whole sweep on stderr (samples done, failed,
elapsed, estimated rest), fed by the sweep's on_sample callback; it never touches a run."""
from __future__ import annotations

import sys
import time


class SweepProgress:
    WIDTH = 30

    def __init__(self, total: int, enabled: bool | None = None, stream=None):
        self.stream = stream or sys.stderr
        self.enabled = (self.stream.isatty() if enabled is None else bool(enabled)) and total > 0
        self.total = total
        self.done = 0
        self.failed = 0
        self.began = time.perf_counter()
        self._last_draw = 0.0

    def advance(self, count: int = 1, failed: int = 0) -> None:
        self.done += count
        self.failed += failed
        now = time.perf_counter()
        if self.enabled and (now - self._last_draw > 0.1 or self.done >= self.total):
            self._last_draw = now
            self._draw(now)

    def _draw(self, now: float) -> None:
        elapsed = now - self.began
        fraction = min(1.0, self.done / self.total)
        bar = "#" * int(round(fraction * self.WIDTH))
        rest = elapsed / self.done * (self.total - self.done) if self.done else float("nan")
        failed = f", {self.failed} failed" if self.failed else ""
        eta = f", ~{rest:.0f} s left" if self.done < self.total and self.done else ""
        self.stream.write(f"\r[{bar:<{self.WIDTH}}] {self.done}/{self.total} samples{failed}  "
                          f"{elapsed:.1f} s{eta}   ")
        self.stream.flush()

    def close(self) -> None:
        if self.enabled and self._last_draw:
            self.stream.write("\n")
            self.stream.flush()
