"""Grid axes with exact decimal values.

Points of a range are computed in decimal arithmetic and rounded once to float64, so a point that is a
short decimal (0.4, 1e-9) is exactly ``float("0.4")``, ``float("1e-9")`` — the same number a user
types in ``values`` — and the union of ranges and explicit values deduplicates exactly.
"""

from __future__ import annotations

import math
from decimal import Decimal, localcontext

__all__ = ["linear_points", "log_count", "log_points", "union"]

_DIGITS = 50


def _decimal(x: float) -> Decimal:
    # repr is the shortest decimal that rounds to x: 0.4 → Decimal("0.4"), not 0.40000000000000002220...
    return Decimal(repr(float(x)))


def linear_points(start: float, stop: float, num: int) -> list[float]:
    """``num`` evenly spaced points from ``start`` to ``stop`` (both included), each rounded once."""
    a, b = _decimal(start), _decimal(stop)
    with localcontext() as ctx:
        ctx.prec = _DIGITS
        return [float(a + (b - a) * k / (num - 1)) for k in range(num)]


def log_count(start: float, stop: float, per_decade: int) -> int:
    """Points of a log axis with at least ``per_decade`` points per decade, both ends included."""
    with localcontext() as ctx:
        ctx.prec = _DIGITS
        decades = abs(_decimal(stop).log10() - _decimal(start).log10())
        intervals = decades * per_decade
        # 12 decades × 4 is 48 intervals exactly; do not let a last-digit residue make it 49
        n = math.ceil(intervals - Decimal("1e-30"))
    return max(n, 1) + 1


def log_points(start: float, stop: float, num: int) -> list[float]:
    """``num`` log-spaced points from ``start`` to ``stop``; exact powers of ten stay exact (1e-9)."""
    a, b = _decimal(start), _decimal(stop)
    with localcontext() as ctx:
        ctx.prec = _DIGITS
        la, lb = a.log10(), b.log10()
        points = [float(Decimal(10) ** (la + (lb - la) * k / (num - 1))) for k in range(num)]
    points[0], points[-1] = float(start), float(stop)
    return points


def union(*groups) -> tuple[float, ...]:
    """Sorted union of float groups, exact duplicates removed."""
    return tuple(sorted({float(x) for group in groups for x in group}))
