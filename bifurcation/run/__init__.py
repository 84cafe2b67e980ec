"""Running workflows on Dask: ``submit`` (resumable, fault-tolerant) and the pipeline benchmark."""

from .submission import WRITERS, Summary, submit

__all__ = ["Summary", "WRITERS", "submit"]
