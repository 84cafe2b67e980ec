"""Progress of a submit, for a terminal, a batch log or a notebook.

On a terminal a tqdm bar (points, rate, ETA); anywhere else (a batch job's log, a pipe, a notebook's
captured stderr) a plain line every ``interval`` seconds and one at the end, so a log shows how far a
study is without a terminal; or a user callback.
"""

from __future__ import annotations

import sys
import time

from ..store.status import format_eta, format_rate

__all__ = ["EVENT_INTERVAL", "Progress", "event_lines", "format_eta"]

#: Seconds between two plain progress lines when stderr is not a terminal.
LOG_INTERVAL = 30.0
#: Seconds between two lines of a long event-by-event run (``bifurcation chain``, ``study chain``'s runs).
EVENT_INTERVAL = 10.0


def event_lines(label: str, started: float | None = None, interval: float | None = None, stream=None):
    """A progress callback ``(done, planned, t)`` of an event-by-event run: a line on stderr at most every
    ``interval`` seconds (``EVENT_INTERVAL``), "bifurcation: LABEL: DONE of PLANNED events, t = T, S s"."""
    started = time.perf_counter() if started is None else started
    last = [started]

    def report(done: int, planned: int, t: float) -> None:
        now = time.perf_counter()
        if now - last[0] >= (EVENT_INTERVAL if interval is None else interval):
            last[0] = now
            out = stream or sys.stderr
            out.write(f"bifurcation: {label}: {done} of {planned} events, t = {t:.6g}, {now - started:.0f} s\n")
            out.flush()

    return report


class Progress:
    """How a submit reports progress.

    Parameters
    ----------
    progress : None, bool or callable
        None: a bar if ``stream`` is a terminal, else plain lines every ``interval`` seconds;
        True: the bar (or lines, off a terminal); False: nothing; a callable: called as
        ``progress(points_done, points_total)`` after every finished tile, nothing printed.
    total : int
        Points to compute.
    """

    def __init__(self, progress, total: int, stream=None, interval: float = LOG_INTERVAL) -> None:
        self.stream = stream or sys.stderr
        self.callback = progress if callable(progress) else None
        self.show = progress is not False and self.callback is None
        tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self.total, self.done, self.interval = total, 0, interval
        self.start = self.last = time.perf_counter()
        self.bar = None
        if self.show and tty:
            from tqdm import tqdm

            self.bar = tqdm(total=total, unit=" points", file=self.stream, dynamic_ncols=True,
                            desc="bifurcation", smoothing=0.1)

    def begin(self) -> None:
        """Start the clock of the rate and the ETA (when the first task goes out, not at start-up)."""
        self.start = self.last = time.perf_counter()

    def note(self, text: str) -> None:
        """One line of what the submit is doing (starting a cluster, waiting for workers)."""
        if self.show:
            (self.bar.write if self.bar is not None else self._line)(f"bifurcation: {text}")

    def _line(self, text: str) -> None:
        self.stream.write(text + "\n")
        self.stream.flush()

    def status_line(self) -> str:
        elapsed = time.perf_counter() - self.start
        rate = self.done / elapsed if elapsed > 0 else 0.0
        eta = (self.total - self.done) / rate if rate > 0 else float("nan")
        percent = 100 * self.done / self.total if self.total else 100.0
        return (f"bifurcation: {self.done}/{self.total} points ({percent:.1f}%), {format_rate(rate)}, "
                f"{elapsed:.1f} s elapsed, ETA {format_eta(eta)}")

    def update(self, points: int) -> None:
        self.done += points
        if self.callback is not None:
            self.callback(self.done, self.total)
        elif self.bar is not None:
            self.bar.update(points)
        elif self.show:
            now = time.perf_counter()
            if now - self.last >= self.interval:
                self.last = now
                self._line(self.status_line())

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
        elif self.show and self.done:
            self._line(self.status_line())
