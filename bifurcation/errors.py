"""Errors raised for bad user input.

Every input error names the argument, shows the value and says how to fix it, so the CLI can print it
as one line (exit status 2) and tests can match the text.
"""

from __future__ import annotations

from contextlib import contextmanager

__all__ = ["InputError", "Terminated", "shown_path", "stop", "uninterrupted"]


class InputError(ValueError):
    """Bad user input: ``argument``, the offending ``value`` and the ``fix``."""

    def __init__(self, argument: str, value: object, problem: str, fix: str) -> None:
        self.argument = argument
        self.value = value
        self.problem = problem
        self.fix = fix
        super().__init__(self.line())

    def line(self, argument: str | None = None) -> str:
        """``argument=value: problem; fix`` (``argument`` as the user typed it, default the one given); a
        value of None is an argument not given: ``--law is missing; give ...``, not ``--law=None: ...``."""
        argument = _shorten(self.argument if argument is None else argument)
        if self.value is None:
            return f"{argument} {self.problem}; {self.fix}"
        return f"{argument}={_shorten(repr(self.value))}: {self.problem}; {self.fix}"


def shown_path(path) -> str:
    """``path`` as printed in a line of output: as it is, or repr-escaped ('a\\nb.zarr', quoted) where it holds
    a character that is not printable (a line break, a tab, an escape, a zero-width space), so that a store's
    name cannot split or hide a line (`status` of a store named "a<newline>b.zarr" printed its header on two
    lines, walk 6). The one helper every command printing a path uses."""
    text = str(path)
    return text if text.isprintable() else repr(text)


#: A name or value longer than this is cut in the error line (a 10^5-character TOML key or law was printed
#: whole: one "line" of 100 kB).
_SHOWN_MAX = 500


def _shorten(text: str) -> str:
    text = str(text)
    if len(text) <= _SHOWN_MAX:
        return text
    return f"{text[:300]}... ({len(text)} characters)"


class Terminated(BaseException):
    """A command stopped by SIGTERM or SIGHUP (``cli``'s handler calls ``stop``). A BaseException like
    KeyboardInterrupt, so that no ``except Exception`` (a tile's retry) swallows it and every ``finally``
    (the store's lock, the helper pool) runs; not a KeyboardInterrupt, which click turns into Abort."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum


class _Stop:
    depth = 0                    # open ``uninterrupted`` blocks
    pending: int | None = None   # a signal that arrived inside one


def stop(signum: int) -> None:
    """Raise ``Terminated(signum)`` now, or at the end of the open ``uninterrupted`` block (for SIGINT,
    Ctrl-C, a ``KeyboardInterrupt``: click and the CLI treat it as an interruption, status 130)."""
    if _Stop.depth:
        _Stop.pending = signum
        return
    _raise(signum)


def _raise(signum: int):
    import signal

    if signum == signal.SIGINT:
        raise KeyboardInterrupt
    raise Terminated(signum)


@contextmanager
def uninterrupted():
    """A stop signal that arrives inside waits until the block ends: a tile's write (its data, then
    ``done``, its checkpoints) is never cut in two by a SIGTERM (found: a submit terminated mid-write left
    data without ``done``, which ``verify`` reports as damage; a Ctrl-C likewise, tests/test_interrupt_write.py)."""
    _Stop.depth += 1
    try:
        yield
    finally:
        _Stop.depth -= 1
    if not _Stop.depth and _Stop.pending is not None:
        signum, _Stop.pending = _Stop.pending, None
        _raise(signum)
