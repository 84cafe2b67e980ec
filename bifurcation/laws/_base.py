"""The friction-law contract.

A law is the function Φ of Eq. (2) of Vasconcelos, PRL 76, 4865 (1996), with Φ(0) = 1 and Φ'(0) = −1
(Eq. 3). The engine never uses Φ itself: it uses the *friction drop* g(x) = 1 − Φ(x), which enters the
scaled equation of motion as Ẅ = t − W + g(νẆ/ν_f)/ν (docs/physics.md). At small x the drop must be
written without cancellation (1 − 1/(1+x) is written x/(1+x)), because it is divided by ν.

A law is a tuple of smooth *pieces* on x ≥ 0: piece k holds on [lower_k, lower_{k+1}). The engine
integrates each piece separately and switches exactly at the breakpoints with events, so a kink is
never smoothed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import mpmath

from ..errors import InputError

__all__ = ["CONTINUITY_RTOL", "FrictionLaw", "Piece"]

#: Two pieces meet at a breakpoint when their drops agree to this, relative to max(1, |g|). The checks
#: work at dps 40 (here) and 60 (the formula parser), so the pieces of a continuous law agree to ~1e-38
#: or better, and any jump someone means is far larger.
CONTINUITY_RTOL = mpmath.mpf("1e-25")


@dataclass(frozen=True)
class Piece:
    """One smooth piece of a friction law.

    Parameters
    ----------
    lower : float
        Left end of the piece in x = U̇/ν_f (0 for the first piece).
    drop : callable
        ``drop(x, num)`` returns the heyoka expression of g(x) = 1 − Φ(x) on this piece; ``num`` turns
        a constant into a heyoka number of the integrator's precision (double or real128).
    drop_mp : callable
        The same g(x) in mpmath, at the working precision of the caller.
    text : str
        Φ on this piece, for people.
    """

    lower: float
    drop: Callable
    drop_mp: Callable
    text: str


@dataclass(frozen=True)
class FrictionLaw:
    """A velocity-weakening friction law Φ(x), x = U̇/ν_f ≥ 0.

    Checked on construction: pieces ordered with the first at x = 0, Φ(0) = 1 and Φ'(0) = −1 (Eq. 3),
    and Φ continuous at every breakpoint (Eq. 2 assumes a continuous Φ).
    """

    name: str
    pieces: tuple[Piece, ...]
    formula: str
    equation: str = ""
    source: str = ""
    description: str = ""
    #: Dropped from comparisons and hashing: two laws are the same law when their names are.
    _taylor_cache: dict = field(default_factory=dict, compare=False, repr=False, hash=False)

    def __post_init__(self) -> None:
        if not self.pieces:
            raise InputError("law", self.formula, "has no pieces", "give at least one piece")
        if self.pieces[0].lower != 0.0:
            raise InputError("law", self.formula, "first piece does not start at x = 0",
                             "start the first piece at x = 0")
        lowers = [p.lower for p in self.pieces]
        if any(b <= a for a, b in zip(lowers, lowers[1:])) or not all(map(math.isfinite, lowers)):
            raise InputError("law", self.formula, f"breakpoints {lowers[1:]} are not finite and increasing",
                             "give increasing finite breakpoints")
        _check_eq3(self)

    # -- evaluation in mpmath (references, checks, the manifold series) -------------------------
    @property
    def breakpoints(self) -> tuple[float, ...]:
        """x values where the law switches piece."""
        return tuple(p.lower for p in self.pieces[1:])

    def piece_index(self, x: float) -> int:
        """Index of the piece that holds at x (right-continuous at the breakpoints)."""
        k = 0
        for i, p in enumerate(self.pieces):
            if x >= p.lower:
                k = i
        return k

    def drop_mp(self, x):
        """g(x) = 1 − Φ(x) in mpmath."""
        return self.pieces[self.piece_index(float(x))].drop_mp(mpmath.mpf(x))

    def phi_mp(self, x):
        """Φ(x) in mpmath."""
        return 1 - self.drop_mp(x)

    def phi(self, x: float) -> float:
        """Φ(x) in double precision (for plots)."""
        return float(self.phi_mp(x))

    def drop_taylor(self, order: int, dps: int = 60) -> list:
        """Taylor coefficients c_0..c_order of g at x = 0 (c_0 = 0, c_1 = 1 by Eq. 3), mpmath numbers."""
        key = (order, dps)
        if key not in self._taylor_cache:
            with mpmath.workdps(dps):
                first = self.pieces[0].drop_mp
                coeffs = mpmath.taylor(first, 0, order, method="step")
            self._taylor_cache[key] = [mpmath.mpf(c) for c in coeffs]
        return self._taylor_cache[key]


def _check_eq3(law: FrictionLaw) -> None:
    """Refuse a law with Φ(0) ≠ 1 or Φ'(0) ≠ −1 (Eq. 3), or a discontinuous Φ."""
    with mpmath.workdps(40):
        first = law.pieces[0].drop_mp
        try:
            g0 = first(mpmath.mpf(0))
            g1 = mpmath.diff(first, 0, 1, direction=1)
        except (ValueError, ZeroDivisionError, TypeError, OverflowError) as exc:
            raise InputError("law", law.formula, f"cannot be evaluated at x = 0 ({exc})",
                             "give a formula that is finite at x = 0") from None
        if not (mpmath.isfinite(g0) and abs(g0) < mpmath.mpf("1e-25")):
            raise InputError("law", law.formula, f"has Φ(0) = {mpmath.nstr(1 - g0, 8)}",
                             "Eq. 3 requires Φ(0) = 1; rescale the law")
        if not (mpmath.isfinite(g1) and abs(g1 - 1) < mpmath.mpf("1e-20")):
            # chopped at the test's resolution: a slope of 0 (e^{-x}(1 + x)) shows as 0, not as -5.6e-45
            raise InputError("law", law.formula, f"has Φ'(0) = {mpmath.nstr(mpmath.chop(-g1, 1e-20), 8)}",
                             "Eq. 3 requires Φ'(0) = -1; rescale x so that the slope at 0 is -1")
        for left, right in zip(law.pieces, law.pieces[1:]):
            b = mpmath.mpf(right.lower)
            gl, gr = left.drop_mp(b), right.drop_mp(b)
            if not abs(gl - gr) <= CONTINUITY_RTOL * max(1, abs(gl)):
                raise InputError("law", law.formula,
                                 f"is discontinuous at x = {right.lower} (Φ jumps from "
                                 f"{mpmath.nstr(1 - gl, 8)} to {mpmath.nstr(1 - gr, 8)})",
                                 "Eq. 2 assumes a continuous Φ; make the pieces meet")
