"""Whether numba can keep its compiled functions on disk for this package's chain engines.

``CACHE`` is False when numba has no writable place for its cache (``__pycache__`` beside these files,
else its user cache directory or NUMBA_CACHE_DIR): ``cache=True`` then raises RuntimeError ("no locator
available") at import, e.g. a read-only install run with a read-only HOME. The compiled engine and the
RK4 baselines (this folder) pass ``cache=CACHE`` and compile per process in that case.
"""

from __future__ import annotations

import numba as nb

__all__ = ["CACHE"]


def _probe() -> None:   # a function of this folder: numba locates its cache by the file's directory
    return None


def _disk_cache() -> bool:
    try:
        nb.njit(cache=True)(_probe)
    except RuntimeError:
        return False
    return True


CACHE = _disk_cache()
