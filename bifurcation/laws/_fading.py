r"""Rungs: where a Taylor step must end so that friction that fades is never stepped over.

The problem (docs/engine.md, "Friction that fades"). heyoka sees the friction only through the Taylor
coefficients of g(x(t)) at the start of each step. Where Φ fades faster than any power (e^{−x},
e^{−x−x²}, ...), those coefficients are all proportional to the fading part (for e^{−x}: g = −expm1(−x)
and every coefficient of order ≥ 1 is ∝ 1 + expm1(−x0) = Φ(x0)), and once that part is below the
rounding of g they are zero or noise. A step started there is not limited by friction, so on the way
down (U̇ decreasing) it can cross the whole deceleration and locate the stop on a polynomial in which
friction never came back. Algebraic laws do not have the problem: their Taylor coefficients in x
decay like (x0 + c)^{−n}, so heyoka's step is held to a fraction of x0 + c and friction changes by a
bounded factor per step.

The guarantee. Let u be the unit roundoff (2^−53 double, 2^−113 quad) and, on each piece of the law,

    V(x) = |g'(x)|·max(1, x)

the change of g over the scale on which it can vary within one step. Computed once per law and
precision, in mpmath at 50 digits, from the law's own ``drop_mp`` (so it holds for every law that
passes validation, built-in or formula, smooth or piecewise):

1. *Top.* x_top is where the final negligible stretch begins: V ≤ u/16 on [x_top, x_checked]. Above
   it friction changes g by less than rounding, so a step there loses nothing by not seeing it.
2. *Ladder.* Between x_top and the first x below it where V ≥ θ = 1e-6 (friction visible, item 3),
   rungs x_0 = x_top > x_1 > … are placed so that |g'(x_{k+1})| ≤ e²·|g'(x_k)|, plus one rung at
   that first visible x. Each rung is a terminal event x/x_k − 1 = 0 crossed downward: it only ends
   a step. A step that starts at or below x_k cannot pass x_{k+1}, so the fading part grows by at
   most e² over it; whatever relative error the step's friction coefficients have at its start
   (≤ u·|g|/|g'| from the cancellation above), its friction is wrong by at most ≈ e²·u at its end.
   The same holds for every stretch where V < θ above a stretch where V ≥ θ (a law may fade, come
   back and fade again).
3. *Below the ladder* V ≥ θ: the friction's order-p coefficients (p = 20 double, 40 quad) are at
   least θ·(d/ℓ)^p/p! for a descent d on its scale ℓ, and heyoka keeps the last terms ≤ u of the
   state, so d/ℓ ≤ (p!·u/θ)^{1/p} ≈ 2.6 (double) or 3.1 (quad): the fading part grows by ≤ e^3 per
   step and its rounding error stays a few u.

Algebraic laws have V ≥ θ up to x_checked (1/(1+x): V ≈ 1/x ≥ 1e-5), so they get no rungs and cost
nothing; piecewise laws are handled piece by piece (a constant piece has V = 0 ≤ u/16 throughout:
no rungs). For e^{−x} the ladder is x = 45.2 … 16.5 in steps of 2 in double (16 rungs) and x = 90.2 …
16.5 in quad (38 rungs): quad's ladder is derived for its own u and does not share double's.

``x_checked`` bounds the scan (1e5, or where ``drop_mp`` stops being finite); the engine reaches
x ≈ max U̇/ν_f ≈ 1/ν_f ≤ 2e4 for the ν_f ≥ 1e-4 of ``bifurcation.bounds``. A point that goes beyond it
is reported as ``unresolved`` by the engine, unless the law's last piece is constant over the whole
scan (g' = 0: nothing there to resolve).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import mpmath

from ._base import FrictionLaw

__all__ = ["Ladder", "ladder"]

#: Largest x the scan checks. The engine reaches x = max U̇/ν_f ≈ 1/ν_f ≤ 2e4 for the ν_f ≥ 1e-4 it
#: accepts (``bifurcation.bounds``): a margin of 5.
X_CHECKED = 1.0e5
#: Friction is visible to heyoka's step control where V(x) = |g'(x)|·max(1, x) ≥ VISIBLE.
VISIBLE = 1e-6
#: |g'| may grow by at most this factor between consecutive rungs.
GROWTH = math.exp(2)
_UNIT_ROUNDOFF = {"double": 2.0 ** -53, "quad": 2.0 ** -113}
_DPS = 50


@dataclass(frozen=True)
class Ladder:
    """Rungs (descending x) of one law and precision, and how far its friction was checked."""

    rungs: tuple
    x_checked: float       # math.inf when the last piece is constant over the whole scan


def _grid(lower: float, upper: float) -> list:
    """Scan points on [lower, upper): 1/4 apart up to 32, then 40 per decade (rungs are bisected)."""
    points = [lower + k / 4 for k in range(int((min(upper, 32.0) - lower) * 4) + 1) if lower + k / 4 < upper]
    x = max(32.0, lower)
    while x < upper:
        points.append(x)
        x *= 10 ** 0.025
    return sorted(set(points))


def _slope(drop, x: float):
    """|g'(x)| in mpmath, or None where the drop is not finite (the scan stops there)."""
    try:
        d = mpmath.diff(drop, mpmath.mpf(x))
    except (ValueError, ZeroDivisionError, OverflowError, TypeError):
        return None
    if not isinstance(d, mpmath.mpf) or not mpmath.isfinite(d):
        return None
    return abs(d)


def _between(drop, low: float, high: float, bound) -> float:
    """The x in (low, high) below which |g'| first exceeds ``bound`` (descending from high)."""
    for _ in range(24):
        mid = (low + high) / 2
        slope = _slope(drop, mid)
        if slope is not None and slope > bound:
            low = mid
        else:
            high = mid
    return high


@functools.lru_cache(maxsize=64)
def _scan(drop, lower: float, upper: float) -> tuple[tuple, tuple, float]:
    """|g'| on the scan grid of [lower, upper) (shared by both precisions) and the x checked."""
    grid = _grid(lower, upper)
    points, slopes = [], []
    with mpmath.workdps(_DPS):
        for x in grid:
            slope = _slope(drop, x)
            if slope is None:
                break
            points.append(x)
            slopes.append(slope)
    return tuple(points), tuple(slopes), upper if len(points) == len(grid) else (points or [lower])[-1]


def _piece_rungs(drop, lower: float, upper: float, u: float) -> tuple[list, float, bool]:
    """Rungs of one piece on [lower, upper), the x up to which it was checked, and whether g' = 0."""
    points, slopes, checked = _scan(drop, lower, upper)
    if not points:
        return [], lower, False
    constant = all(s == 0 for s in slopes)
    vis = [s * max(1.0, x) for x, s in zip(points, slopes)]
    top = len(points) - 1
    if vis[top] <= u / 16:
        while top > 0 and vis[top - 1] <= u / 16:
            top -= 1
    rungs: list = []
    rung, current = None, None  # the last rung and its |g'| while inside a stretch with V < VISIBLE
    for i in range(top, -1, -1):
        x, slope = points[i], slopes[i]
        if current is not None:
            while slope > GROWTH * current:  # rungs between the last one and x, GROWTH apart in |g'|
                new = _between(drop, x, rung, GROWTH * current)
                if not x < new < rung:
                    new = x
                rungs.append(new)
                rung, current = new, _slope(drop, new) or slope
                if new == x:
                    break
        if vis[i] >= VISIBLE:
            if current is not None and rung != x:  # the first visible point under a ladder
                rungs.append(x)
            rung = current = None
        elif current is None:  # the top of a stretch where friction is invisible
            rungs.append(x)
            rung, current = x, slope
    return [r for r in rungs if r > lower], checked, constant  # a rung at the left end is the switch


@functools.lru_cache(maxsize=64)
def _ladder(name: str, formula: str, precision: str, law: FrictionLaw) -> Ladder:
    u = _UNIT_ROUNDOFF[precision]
    rungs, checked, constant = [], X_CHECKED, False
    bounds = [p.lower for p in law.pieces] + [X_CHECKED]
    with mpmath.workdps(_DPS):
        for piece, lower, upper in zip(law.pieces, bounds, bounds[1:]):
            if lower >= X_CHECKED:
                break
            r, piece_checked, constant = _piece_rungs(piece.drop_mp, lower, min(upper, X_CHECKED), u)
            rungs.extend(r)
            if piece_checked < min(upper, X_CHECKED):  # the drop stopped being finite: stop here
                checked = piece_checked
                constant = False
                break
    return Ladder(tuple(sorted(set(rungs), reverse=True)), math.inf if constant else checked)


def ladder(law: FrictionLaw, precision: str) -> Ladder:
    """The cached ladder of ``law`` for ``precision`` (computed once per process: 0.1-2 s for the
    built-in laws, up to ~15 s for a formula law, whose mpmath drop is slower)."""
    return _ladder(law.name, law.formula, precision, law)
