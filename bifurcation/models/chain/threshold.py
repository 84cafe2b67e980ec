"""Where a slip confined to one block among stuck neighbours turns from stick-slip to creep.

A block slipping alone feels the stiffness k = 1 + 2ℓ² (interior) or 1 + ℓ² (free end); rescaling
time by √k and displacement by k maps it onto the single block with ν' = ν/√k and ν_f' = √k ν_f
(docs/chain.md, "Threshold of a lone block"). The single block's transition at ν_f' = 1/2 then puts
the lone block's threshold at ν_f* = 1/(2√k). This module gives the closed form and measures the
crossing on the chain engine itself (no rescaling used), so the report can set one against the other.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["lone_block_crossing", "lone_block_nu_f_star", "lone_block_slip", "lone_block_stiffness"]


def lone_block_stiffness(ell: float, end: bool = False) -> float:
    """k = 1 + 2ℓ² for an interior block, 1 + ℓ² for a block at a free end."""
    return 1.0 + (1.0 if end else 2.0) * ell * ell


def lone_block_nu_f_star(ell: float, end: bool = False) -> float:
    r"""Closed-form threshold of a lone slipping block, :math:`\nu_f^* = 1/(2\sqrt{k})` (docs/chain.md)."""
    return 0.5 / math.sqrt(lone_block_stiffness(ell, end))


def lone_block_slip(law, *, ell: float, nu: float, nu_f: float, end: bool = False) -> float:
    """Potency of the first event of a chain whose only loaded block slips alone.

    Interior: N = 5, block 2 displaced by −c (σ_2(0) = ck = 1/2, neighbours at −ℓ²c, the rest 0).
    Free end: N = 3, block 0 displaced likewise. The neighbours stay far below the threshold for any
    slip Δ/k with Δ < 2.2 (they gain ℓ²P), and the event must involve that block only: a run where it
    does not raises ``RuntimeError`` rather than return a number that is not the lone block's.
    """
    from .simulate import chain

    k = lone_block_stiffness(ell, end)
    n, j = (3, 0) if end else (5, 2)
    u0 = np.zeros(n)
    u0[j] = -0.5 / k
    r = chain(law, n=n, ell=ell, nu=nu, nu_f=nu_f, u0=u0, events=1)
    if r.events != 1 or r.hypocentre[0] != j or r.n_blocks[0] != 1:
        raise RuntimeError(f"the lone-block event did not stay on block {j} (ℓ = {ell}, ν_f = {nu_f}): "
                           f"status {r.status}, n_blocks {r.n_blocks.tolist()}")
    return float(r.potency[0])


def lone_block_crossing(law, *, ell: float, nu: float, end: bool = False, level: float = 0.01,
                        rel_tol: float = 1e-6) -> dict:
    """The ν_f where the lone block's slip k·P falls through ``level``, by bisection on the engine.

    k·P is the rescaled single block's Δ: O(1) in stick-slip (≥ Δ0(1/2) = 0.1507 for carlson-langer, docs/physics.md),
    O(ν) in creep, so for ν ≪ ``level`` the crossing tends to ν_f* as ν → 0 whatever the level. The
    bracket is [0.8, 1.25]·ν_f*; a bracket that does not straddle the level gives NaN.
    """
    k = lone_block_stiffness(ell, end)
    star = lone_block_nu_f_star(ell, end)
    lo, hi = 0.8 * star, 1.25 * star
    p_lo = k * lone_block_slip(law, ell=ell, nu=nu, nu_f=lo, end=end)
    p_hi = k * lone_block_slip(law, ell=ell, nu=nu, nu_f=hi, end=end)
    out = {"ell": ell, "end": end, "nu": nu, "k": k, "nu_f_star": star, "level": level,
           "delta_below": p_lo, "delta_above": p_hi}
    if not (p_lo > level > p_hi):
        return {**out, "nu_f_cross": math.nan, "relative_offset": math.nan}
    while hi - lo > rel_tol * star:
        mid = 0.5 * (lo + hi)
        if k * lone_block_slip(law, ell=ell, nu=nu, nu_f=mid, end=end) > level:
            lo = mid
        else:
            hi = mid
    cross = 0.5 * (lo + hi)
    return {**out, "nu_f_cross": cross, "relative_offset": cross / star - 1}
