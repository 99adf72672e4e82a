"""The accuracy study's progress line (`Progress`) and the duration format it shares with the
generated report."""

from __future__ import annotations

import math
import sys
import time


class Progress:
    """The sweep's progress bar (tqdm: elapsed, estimated time left, the current block) on a
    terminal; silent when the stream is not one (a log, CI, a pipe), so files stay clean.
    `advance(amount, what)` adds work done, in the same units as `total`."""

    def __init__(self, total: float, stream=None):
        from tqdm import tqdm

        self.total = max(total, 1e-9)
        self.stream = stream if stream is not None else sys.stderr
        self.start = time.perf_counter()
        tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self._bar = tqdm(
            total=self.total, file=self.stream, disable=not tty, leave=True, dynamic_ncols=True,
            bar_format="{percentage:3.0f}%|{bar}| {elapsed} elapsed, ~{remaining} left{postfix}",
        )

    @property
    def done(self) -> float:
        return float(self._bar.n)

    def advance(self, amount: float, what: str) -> None:
        self._bar.set_postfix_str(what, refresh=False)
        self._bar.update(min(amount, self.total - self._bar.n))
        if self._bar.n >= self.total:
            self._bar.close()


def format_duration(seconds: float) -> str:
    if not math.isfinite(seconds):
        return "?"
    seconds = int(round(seconds))
    return f"{seconds // 60}m{seconds % 60:02d}s" if seconds >= 60 else f"{seconds}s"
