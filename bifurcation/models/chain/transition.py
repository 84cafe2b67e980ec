"""A defined transition point and its finite-size scaling (issue 17, item 5).

The report's "jump" was the largest difference between neighbouring grid values, which sits wherever the
grid puts it (it moved between ν_f = 0.15 and 0.4 with N). The transition of the order parameter D(ν_f)
(docs/chain.md, "Order parameter": mean ± seed-to-seed error) is located by crossing.py's half-way
crossing ν_½ (``crossing.locate``: between D at the smallest ν_f and the lower plateau found from the data,
bootstrap and grid errors in quadrature; the one implementation, shared with the chain report).

Here the locations per N are fitted as ν_f*(N) = ν_f*(∞) + A N^−θ (weighted least squares, linear in
ν_f*(∞) and A for each θ on a grid, θ by the smallest χ²; the errors of ν_f*(∞) and A at that θ from
the normal equations). With three N values the fit has zero degrees of freedom: it interpolates, and
the report must say so.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["scale_transition"]


def scale_transition(sizes, locations, sigmas, *, thetas=None) -> dict:
    """Fit ν_f*(N) = ν_f*(∞) + A N^−θ to the transition points of several N (see the module text)."""
    n, y, s = (np.asarray(a, dtype=float) for a in (sizes, locations, sigmas))
    ok = np.isfinite(y) & np.isfinite(s) & (s > 0)
    n, y, s = n[ok], y[ok], s[ok]
    if n.size < 3:
        return {"limit": math.nan, "limit_sigma": math.nan, "amplitude": math.nan, "theta": math.nan,
                "chi2": math.nan, "dof": n.size - 3, "reason": "needs transition points at ≥ 3 sizes"}
    thetas = np.linspace(0.05, 3.0, 296) if thetas is None else np.asarray(thetas, dtype=float)
    best = None
    for th in thetas:
        a = np.column_stack((np.ones_like(n), n**-th)) / s[:, None]     # rows weighted by 1/σ
        coef, *_ = np.linalg.lstsq(a, y / s, rcond=None)
        chi2 = float(np.sum((y / s - a @ coef) ** 2))
        if best is None or chi2 < best[0]:
            best = (chi2, th, coef, np.linalg.pinv(a.T @ a))
    chi2, th, coef, cov = best
    return {"limit": float(coef[0]), "limit_sigma": float(math.sqrt(cov[0, 0])), "amplitude": float(coef[1]),
            "theta": float(th), "chi2": chi2, "dof": int(n.size - 3),
            "reason": "" if n.size > 3 else "3 sizes for 3 parameters: the fit interpolates (no test of the form)"}


#: longest event (in loading cycles) beyond which a step's events are merged slides (as the report's rule)
MERGED_CYCLES = 0.5

#: the small study of docs/chain.md, "A defined transition": (law, ℓ, ν, σ values, N values, ν_f grid, seeds)
STUDY = ("carlson-langer", 1.0, 1e-3, (0.0, 0.01), (1, 4, 16, 64), tuple(round(0.3 + 0.05 * i, 2) for i in range(11)),
         (1, 2, 3))


def main() -> None:
    """Per σ and N: D(ν_f) over seeds (sweep up), its half-way crossing (crossing.locate), the fit over N."""
    import time

    from .analysis import sweep_nu_f
    from .crossing import locate

    law, ell, nu, sigmas, sizes, grid, seeds = STUDY
    grid = np.asarray(grid)
    for sigma in sigmas:
        points = []
        for n in sizes:
            t0 = time.process_time()
            runs = [sweep_nu_f(law, n=n, ell=ell, nu=nu, nu_f_values=grid, cycles_per_step=3.0, seed=s,
                               amplitude=0.5, sigma=sigma, max_events_per_step=20_000) for s in seeds]
            d = np.array([r["slip_per_block"] for r in runs])
            mean, se = d.mean(axis=0), d.std(axis=0, ddof=1) / math.sqrt(len(seeds))
            # D measures a block's slip only while events stay separate: a step whose longest event lasts
            # more than half a loading cycle holds merged slides (docs/chain.md, "Order parameter") and is
            # left out (NaN), as in the chain report's sweeps
            longest = np.max([r["longest_event"] for r in runs], axis=0)
            merged = longest > MERGED_CYCLES
            mean[merged] = np.nan
            hc = locate(grid, mean, se)["half"]
            gone = ", ".join(f"{v:g}" for v in grid[merged])
            left_out = f"; left out (merged): ν_f = {gone}" if merged.any() else ""
            points.append((n, hc["value"], hc["sigma"]))
            print(f"sigma={sigma} N={n}: D = {np.array2string(mean, precision=4)} ± max {se.max():.2g}; "
                  f"half-way crossing {hc['value']:.4f} ± {hc['sigma']:.4f} ({hc['status']}{left_out}) "
                  f"({time.process_time() - t0:.0f} CPU s)", flush=True)
        fit = scale_transition(*zip(*points))
        print(f"sigma={sigma}: nu_f*(inf) = {fit['limit']:.4f} ± {fit['limit_sigma']:.4f}, theta = {fit['theta']:.2f}, "
              f"dof = {fit['dof']} {fit['reason']}", flush=True)


if __name__ == "__main__":
    main()
