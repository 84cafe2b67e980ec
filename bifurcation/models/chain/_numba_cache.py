"""Whether numba can keep its compiled functions on disk for this package's chain engines, and a cache
that also goes stale when a file the compiled code depends on changes.

``CACHE`` is False when numba has no writable place for its cache (``__pycache__`` beside these files,
else its user cache directory or NUMBA_CACHE_DIR): ``cache=True`` then raises RuntimeError ("no locator
available") at import, e.g. a read-only install run with a read-only HOME. The compiled engine and the
RK4 baselines (this folder) pass ``cache=CACHE`` and compile per process in that case.

numba checks a cached function against the file that defines it only: the compiled engine also freezes
``_dop853``'s coefficients into its code and interprets ``_lawtape``'s tapes and ``_lone``'s tables,
so an edit there alone would leave a stale engine on disk. ``jit(depends=...)`` folds a hash of those
files into the stamp numba checks its cache index against: a change makes the index stale, the
function is compiled again and the index rewritten (no directory per version piles up).
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import numba as nb

__all__ = ["CACHE", "jit", "source_key"]


def _probe() -> None:   # a function of this folder: numba locates its cache by the file's directory
    return None


def _disk_cache() -> bool:
    try:
        nb.njit(cache=True)(_probe)
    except RuntimeError:
        return False
    return True


CACHE = _disk_cache()


def source_key(paths) -> str:
    """sha256 of the files' names and contents (order-free): the part of the cache stamp numba does not see."""
    h = hashlib.sha256()
    for p in sorted(Path(p) for p in paths):
        h.update(p.name.encode() + b"\0" + p.read_bytes() + b"\0")
    return h.hexdigest()


def jit(*, depends=(), **options):
    """``numba.njit(cache=CACHE, **options)`` whose disk cache is also stale when a file of ``depends``
    changes. Sets numba's (private) ``_cache._cache_file._source_stamp``: tests/test_numba_cache.py
    fails if a numba release moves it."""
    key = source_key(depends) if depends else None

    def decorate(func):
        disp = nb.njit(cache=CACHE, **options)(func)
        cache_file = getattr(getattr(disp, "_cache", None), "_cache_file", None)   # None without a disk cache
        if key is not None and cache_file is not None:
            cache_file._source_stamp = (cache_file._source_stamp, key)
        return disp

    return decorate
