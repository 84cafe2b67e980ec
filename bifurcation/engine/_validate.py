"""Validation of engine arguments: one-line errors naming the argument, the value and the fix."""

from __future__ import annotations

import numpy as np

from ..bounds import NU_BOUNDS, NU_F_BOUNDS, check_max_steps, check_t_max, in_bounds_fix
from ..errors import InputError

__all__ = ["check_batch", "check_nu", "check_nu_f", "check_precision", "check_work"]

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


def _in_bounds(name: str, arr: np.ndarray, bounds) -> np.ndarray:
    low, high = bounds
    bad = (arr < low) | (arr > high)
    if bad.any():
        first = arr[bad].ravel()[0] if arr.ndim else float(arr)
        raise InputError(name, float(first), f"is outside [{low:g}, {high:g}]", in_bounds_fix(name))
    return arr


def check_nu(nu) -> np.ndarray:
    """ν: finite, > 0 and within ``bifurcation.bounds.NU_BOUNDS`` (the pulling speed of Eq. 5)."""
    return _in_bounds("nu", _positive_finite("nu", nu, "give a pulling speed ν > 0 such as 1e-9"), NU_BOUNDS)


def check_nu_f(nu_f) -> np.ndarray:
    """ν_f: finite, > 0 and within ``bifurcation.bounds.NU_F_BOUNDS`` (the friction velocity of Eq. 2)."""
    return _in_bounds("nu_f", _positive_finite("nu_f", nu_f, "give a friction velocity ν_f > 0 such as 0.4"),
                      NU_F_BOUNDS)


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


def check_work(t_max, max_steps) -> None:
    """``t_max`` and ``max_steps`` within ``bifurcation.bounds`` (a cycle that can never end is refused)."""
    try:
        t = float(t_max)
    except (TypeError, ValueError):
        raise InputError("t_max", t_max, "is not a number", "give a time such as 1e5") from None
    check_t_max("t_max", t)
    check_max_steps("max_steps", int(max_steps) if isinstance(max_steps, np.integer) else max_steps)
