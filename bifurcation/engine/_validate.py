"""Validation of engine arguments: one-line errors naming the argument, the value and the fix."""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["check_batch", "check_nu", "check_nu_f", "check_precision"]

PRECISIONS = ("double", "quad")


def _positive_finite(name: str, value, fix: str) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(name, value, "is not a number", fix) from None
    bad = ~np.isfinite(arr) | (arr <= 0)
    if bad.any():
        first = arr[bad].ravel()[0] if arr.ndim else float(arr)
        raise InputError(name, float(first), "must be finite and > 0", fix)
    return arr


def check_nu(nu) -> np.ndarray:
    """ν: finite, > 0 (the pulling speed of Eq. 5)."""
    return _positive_finite("nu", nu, "give a pulling speed ν > 0 such as 1e-9")


def check_nu_f(nu_f) -> np.ndarray:
    """ν_f: finite, > 0 (the friction velocity of Eq. 2)."""
    return _positive_finite("nu_f", nu_f, "give a friction velocity ν_f > 0 such as 0.4")


def check_precision(precision: str) -> str:
    if precision not in PRECISIONS:
        raise InputError("precision", precision, "is not a precision", "use 'double' or 'quad'")
    return precision


def check_batch(batch, precision: str) -> int:
    """Batch lanes: an integer ≥ 1; batches are double precision only."""
    if isinstance(batch, bool) or not isinstance(batch, (int, np.integer)) or batch < 1:
        raise InputError("batch", batch, "is not a lane count", "give an integer ≥ 1 (e.g. 8), or 1 for scalar")
    if batch > 1 and precision != "double":
        raise InputError("batch", batch, f"is not available with precision={precision!r}",
                         "use batch=1 for quad precision")
    return int(batch)
