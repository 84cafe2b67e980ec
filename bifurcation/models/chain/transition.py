"""A defined transition point and its finite-size scaling (issue 17, item 5).

The report's "jump" was the largest difference between neighbouring grid values, which sits wherever the
grid puts it (it moved between ν_f = 0.15 and 0.4 with N). Here the transition of a per-step order
parameter y(ν_f) (docs/chain.md, "Order parameter": D or Ψ, mean ± seed-to-seed error) is located where
y crosses **half its jump**: level = (y_before + y_after)/2 with y_before, y_after the means of the first
and last ``plateau`` points of the sweep; the crossing is the linear interpolation between the two
grid points that bracket the level (the first sign change). Its error comes from the errors of y:
the crossing is recomputed for ``draws`` Gaussian perturbations of every y_i by its σ_i (plateaus and
bracket included), and the grid's error is the difference to the same bracket interpolated in ln y;
the error given is both in quadrature (``statistical``, ``grid`` apart). A sweep whose plateaus differ by less than 2σ,
or that never crosses its level, has no transition (NaN, ``reason`` says why).

The locations per N are then fitted as ν_f*(N) = ν_f*(∞) + A N^−θ (weighted least squares, linear in
ν_f*(∞) and A for each θ on a grid, θ by the smallest χ²; the errors of ν_f*(∞) and A at that θ from
the normal equations). With three N values the fit has zero degrees of freedom: it interpolates, and
the report must say so.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["half_crossing", "scale_transition"]


def _crossing(x, y, plateau, log=False):
    hi, lo = float(np.mean(y[:plateau])), float(np.mean(y[-plateau:]))
    level = 0.5 * (hi + lo)
    d = y - level
    for i in range(len(x) - 1):
        if d[i] == 0:
            return float(x[i]), level, i
        if d[i] * d[i + 1] < 0:
            if log and y[i] > 0 and y[i + 1] > 0:     # the same bracket, interpolated in ln y
                f = (math.log(level) - math.log(y[i])) / (math.log(y[i + 1]) - math.log(y[i]))
            else:
                f = (level - y[i]) / (y[i + 1] - y[i])
            return float(x[i] + f * (x[i + 1] - x[i])), level, i
    return math.nan, level, -1


def half_crossing(nu_f, values, sigmas, *, plateau: int = 2, draws: int = 2000, seed: int = 0) -> dict:
    """Where ``values`` (over the increasing ``nu_f``) cross half their jump, with its error."""
    x, y, s = (np.asarray(a, dtype=float) for a in (nu_f, values, sigmas))
    if not (x.ndim == y.ndim == s.ndim == 1 and x.size == y.size == s.size):
        raise ValueError("nu_f, values and sigmas must be 1-d arrays of one length")
    if x.size < 2 * plateau + 1 or np.any(np.diff(x) <= 0):
        return {"nu_f": math.nan, "sigma": math.nan, "level": math.nan, "bracket": None,
                "reason": f"needs ≥ {2 * plateau + 1} increasing ν_f values"}
    jump = abs(np.mean(y[:plateau]) - np.mean(y[-plateau:]))
    jump_sigma = math.sqrt(np.sum(s[:plateau] ** 2) + np.sum(s[-plateau:] ** 2)) / plateau
    if not jump > 2 * jump_sigma:
        return {"nu_f": math.nan, "sigma": math.nan, "level": math.nan, "bracket": None,
                "reason": f"no jump beyond 2σ between the plateaus ({jump:.3g} ± {jump_sigma:.3g})"}
    xc, level, i = _crossing(x, y, plateau)
    if not math.isfinite(xc):
        return {"nu_f": math.nan, "sigma": math.nan, "level": level, "bracket": None,
                "reason": "the order parameter never crosses half its jump"}
    rng = np.random.default_rng(seed)
    got = [_crossing(x, y + rng.standard_normal(y.size) * s, plateau)[0] for _ in range(draws)]
    got = np.asarray(got)
    ok = np.isfinite(got)
    statistical = float(np.std(got[ok], ddof=1)) if ok.sum() > 1 else math.nan
    # the grid's own error: the same bracket interpolated in ln y instead of y (a curve that falls by a
    # factor across the bracket is far from linear there); zero only where the two agree
    grid = abs(_crossing(x, y, plateau, log=True)[0] - xc)
    return {"nu_f": xc, "sigma": math.hypot(statistical, grid), "statistical": statistical, "grid": grid,
            "level": level, "bracket": (float(x[i]), float(x[i + 1])), "lost": int((~ok).sum()),
            "reason": ""}


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
    """Per σ and N: D(ν_f) over seeds (sweep up), its half-jump crossing, and the fit over N."""
    import time

    from .analysis import sweep_nu_f

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
            se = np.maximum(se, 1e-12)
            # D measures a block's slip only while events stay separate: from the first step whose
            # longest event lasts more than half a loading cycle, events merge (docs/chain.md, "Order
            # parameter") and D measures merged slides; the sweep is cut there
            longest = np.max([r["longest_event"] for r in runs], axis=0)
            merged = np.flatnonzero(longest > MERGED_CYCLES)
            cut = int(merged[0]) if merged.size else len(grid)
            hc = half_crossing(grid[:cut], mean[:cut], se[:cut])
            if cut < len(grid):
                hc["reason"] = (hc["reason"] + "; " if hc["reason"] else "") + \
                    f"events merge from ν_f = {grid[cut]} on (sweep cut there)"
            points.append((n, hc["nu_f"], hc["sigma"]))
            print(f"sigma={sigma} N={n}: D = {np.array2string(mean, precision=4)} ± max {se.max():.2g}; "
                  f"half-jump crossing {hc['nu_f']:.4f} ± {hc['sigma']:.4f} {hc['reason']} "
                  f"({time.process_time() - t0:.0f} CPU s)", flush=True)
        fit = scale_transition(*zip(*points))
        print(f"sigma={sigma}: nu_f*(inf) = {fit['limit']:.4f} ± {fit['limit_sigma']:.4f}, theta = {fit['theta']:.2f}, "
              f"dof = {fit['dof']} {fit['reason']}", flush=True)


if __name__ == "__main__":
    main()
