"""The accuracy study's progress line (`Progress`) and the duration format it shares with the
generated report."""

from __future__ import annotations

import math
import sys
import time


class Progress:
    """A one-line progress report on a stream: overwritten in place on a terminal, one line
    per update (at most every few seconds) elsewhere."""

    def __init__(self, total: float, stream=None, every: float = 5.0):
        self.total = max(total, 1e-9)
        self.done = 0.0
        self.stream = stream if stream is not None else sys.stderr
        self.start = time.perf_counter()
        self.every = every
        self._last = -math.inf
        self._tty = bool(getattr(self.stream, "isatty", lambda: False)())

    def advance(self, amount: float, what: str) -> None:
        self.done = min(self.done + amount, self.total)
        now = time.perf_counter()
        if not self._tty and now - self._last < self.every and self.done < self.total:
            return
        self._last = now
        elapsed = now - self.start
        fraction = self.done / self.total
        left = elapsed * (1.0 - fraction) / fraction if fraction > 0 else float("nan")
        line = f"[{fraction:4.0%}] {_duration(elapsed)} elapsed, ~{_duration(left)} left: {what}"
        if self._tty:
            self.stream.write("\r\033[K" + line[:150])
            if self.done >= self.total:
                self.stream.write("\n")
        else:
            self.stream.write(line + "\n")
        self.stream.flush()


def _duration(seconds: float) -> str:
    if not math.isfinite(seconds):
        return "?"
    seconds = int(round(seconds))
    return f"{seconds // 60}m{seconds % 60:02d}s" if seconds >= 60 else f"{seconds}s"
