"""The single block with a friction drop σ: its slip Δ(ν, ν_f, σ) and the crossover that replaces the
seed's ν_f = 1/2 transition (docs/physics.md, "A friction drop σ").

    python -m bifurcation.models.chain.drop        # the table of docs/physics.md
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["crossover_estimate", "linear_slip", "single_block_slip", "steepest_descent"]


def single_block_slip(law, nu_f: float, sigma: float, nu: float = 1e-9) -> float:
    """Δ(ν, ν_f, σ): the slip of one block from rest at stress 1 (the chain with N = 1, ℓ = 0)."""
    from .simulate import chain

    r = chain(law, n=1, ell=0.0, nu=nu, nu_f=nu_f, amplitude=0.0, seed=0, events=1, sigma=sigma,
              t_max=1e9, max_steps=10**7)
    return float(r.potency[0]) if r.status == 1 else math.nan


def linear_slip(nu_f: float, sigma: float) -> float:
    """ν → 0 slip while the motion stays linear (ν_f > 1/2): σ(1 + exp(π/√(4ν_f² − 1))); exact for the
    piecewise-linear law while max V < (1 − σ)ν_f."""
    if nu_f <= 0.5:
        return math.nan
    return sigma * (1 + math.exp(math.pi / math.sqrt(4 * nu_f * nu_f - 1)))


def crossover_estimate(sigma: float) -> float:
    """ν_f where the half-turn amplification e^{π/√(4ν_f² − 1)} reaches 1/σ: ½√(1 + π²/ln²(1/σ))."""
    return 0.5 * math.sqrt(1 + math.pi**2 / math.log(1 / sigma) ** 2)


def steepest_descent(law, sigma: float, grid, nu: float = 1e-9) -> dict:
    """The midpoint of the grid interval where ln Δ0 falls fastest, its slope, and Δ0 on the grid."""
    grid = np.asarray(grid, dtype=float)
    d = np.array([single_block_slip(law, x, sigma, nu) for x in grid])
    slope = np.diff(np.log(d)) / np.diff(grid)
    k = int(np.argmin(slope))
    return {"nu_f": float(0.5 * (grid[k] + grid[k + 1])), "slope": float(slope[k]), "slip": d}


def main() -> None:
    grid = np.round(np.arange(0.40, 1.2001, 0.01), 4)
    for law in ("piecewise-linear", "carlson-langer"):
        for sigma in (1e-4, 1e-3, 1e-2, 5e-2):
            out = steepest_descent(law, sigma, grid)
            at = {x: out["slip"][int(round((x - 0.40) / 0.01))] for x in (0.5, 0.6, 1.0)}
            print(f"{law} σ = {sigma:g}: steepest at {out['nu_f']:.3f} (slope {out['slope']:.1f}), estimate "
                  f"{crossover_estimate(sigma):.3f}; Δ0(0.5) = {at[0.5]:.4g}, Δ0(0.6) = {at[0.6]:.4g}, "
                  f"Δ0(1.0) = {at[1.0]:.4g}", flush=True)


if __name__ == "__main__":
    main()
