"""Progress of a submit: a one-line counter on a terminal, or a user callback."""

from __future__ import annotations

import sys
import time

__all__ = ["Progress"]


class Progress:
    """``progress`` None: a counter on stderr if it is a terminal; True / False: force on / off; a
    callable: called as ``progress(points_done, points_total)`` after every finished tile."""

    def __init__(self, progress, total: int, stream=None) -> None:
        self.stream = stream or sys.stderr
        self.callback = progress if callable(progress) else None
        if progress is None:
            progress = bool(getattr(self.stream, "isatty", lambda: False)())
        self.show = bool(progress) and self.callback is None
        self.total, self.done, self.start, self.last = total, 0, time.perf_counter(), 0.0

    def update(self, points: int) -> None:
        self.done += points
        if self.callback is not None:
            self.callback(self.done, self.total)
        now = time.perf_counter()
        if self.show and (now - self.last > 0.1 or self.done >= self.total):
            self.last = now
            percent = 100 * self.done / self.total if self.total else 100
            self.stream.write(f"\rbifurcation: {self.done}/{self.total} points ({percent:.0f}%), "
                              f"{now - self.start:.1f} s ")
            self.stream.flush()

    def close(self) -> None:
        if self.show and self.last:
            self.stream.write("\n")
            self.stream.flush()
