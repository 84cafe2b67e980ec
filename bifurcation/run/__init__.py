"""Running workflows on Dask: the grid cut into ``tiles``, ``submit`` (resumable, fault-tolerant),
progress and repair."""

from .submission import WRITERS, Summary, submit

__all__ = ["Summary", "WRITERS", "submit"]
