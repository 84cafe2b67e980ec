"""A defined transition location per chain size from a ν_f sweep of the order parameter D, and its
finite-size scaling (the chain report's "Finite-size scaling of a defined transition").

The "largest change between neighbouring ν_f" (analysis.hysteresis) sits wherever the grid puts it; here
the transition is located by two definitions that do not depend on which grid interval wins:

* **half-way crossing** ν_½: where D (up branch, falling with ν_f) crosses half-way between its level at
  the smallest ν_f (stick-slip) and its lower plateau (the mean of the points within 10 % of the drop
  above the minimum), by linear interpolation between the two grid points around it;
* **steepest-descent point** ν_χ: the peak of the susceptibility-like −dD/dν_f (finite differences at
  the interval midpoints), located by the vertex of the parabola through the largest difference and its
  two neighbours (a peak on the first or last interval is not located).

Errors: a seeded parametric bootstrap over D's error bars (each D_i drawn from N(D_i, se_i²), the
location recomputed; σ is the draws' standard deviation); for ν_½ the interpolation's own error (the same
bracket interpolated in ln D) is added in quadrature. A fall from D at the smallest ν_f to the plateau's
mean within 2σ of their errors is no transition (no ν_½). The lower plateau is found from the data, not
taken as the grid's last points (at N ≥ 64 the last grid points are the chain's slides, where D rises
again), and steps left out (NaN) are skipped. This is the project's one half-way crossing (transition.py's
small study and the chain report both use it). With the location, the transition's
**width** W = (drop)/(largest −dD/dν_f): the ν_f range a straight ramp of the same steepest slope needs
(W = grid spacing for a step the grid does not resolve).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["PLATEAU_FRACTION", "WINDOW", "grid_error", "half_crossing", "locate", "location_fit", "location_words", "slope_peak"]

#: a lower plateau is the points (past the half-way fall) within this fraction of the drop above the minimum;
#: fewer than two such points is a curve still falling or turning up again (no plateau on the grid)
PLATEAU_FRACTION = 0.1


def _valid(x, y):
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    ok = np.isfinite(y)
    return x[ok], y[ok]


def _lower_plateau(y) -> tuple[np.ndarray | None, str]:
    """The mask of the lower plateau of a falling y with no NaN (see half_crossing), or (None, why not)."""
    if y.size < 3:
        return None, "too few points"
    hi, i_lo = y[0], int(np.argmin(y))
    drop = hi - y[i_lo]
    if not drop > 0 or i_lo == 0:
        return None, "no drop"
    plateau = (y <= y[i_lo] + PLATEAU_FRACTION * drop) & (np.arange(y.size) >= np.argmax(y < hi - drop / 2))
    if plateau.sum() < 2:
        return None, "no lower plateau on the grid"
    return plateau, "ok"


def half_crossing(x, y) -> tuple[float, str]:
    """(ν_½, status) of a falling curve y(x) on an ascending grid; NaN values (steps left out) skipped.

    status "ok", or why there is no crossing: "no lower plateau on the grid" (fewer than two points past
    the half-way fall lie within PLATEAU_FRACTION of the drop above the minimum), "too few points",
    "no drop" (the curve does not fall)."""
    x, y = _valid(x, y)
    plateau, status = _lower_plateau(y)
    if plateau is None:
        return math.nan, status
    lo = float(y[plateau].mean())
    level = 0.5 * (y[0] + lo)
    i = _bracket(y, level, int(np.argmin(y)))
    return float(x[i] + (y[i] - level) / (y[i] - y[i + 1]) * (x[i + 1] - x[i])), "ok"


def _bracket(y, level, i_lo) -> int:
    """The first i < i_lo with y[i] ≥ level > y[i + 1] (there is one: y[0] > level > y[i_lo])."""
    return next(i for i in range(i_lo) if y[i] >= level > y[i + 1])


def grid_error(x, y) -> float:
    """The interpolation's own error of ν_½: the same bracket interpolated in ln y instead of y (D falls by
    a factor across a coarse bracket, so neither is exact); NaN without a crossing."""
    c = half_crossing(x, y)[0]
    x, y = _valid(x, y)
    if not math.isfinite(c) or not np.all(y > 0):
        return math.nan
    i = int(np.searchsorted(x, c, side="right")) - 1
    i = min(i, x.size - 2)
    level = y[i] + (y[i + 1] - y[i]) * (c - x[i]) / (x[i + 1] - x[i])     # the level, read back at ν_½
    f = math.log(level / y[i]) / math.log(y[i + 1] / y[i])
    return float(abs(x[i] + f * (x[i + 1] - x[i]) - c))


def slope_peak(x, y) -> tuple[float, float, str]:
    """(ν_χ, largest −dy/dx, status): the vertex of the parabola through the largest finite difference
    −Δy/Δx (at the interval midpoints) and its neighbours; "peak at the grid's edge" if it is the first or
    last interval, "too few points" below 3 intervals. Needs equal spacing around the peak."""
    x, y = _valid(x, y)
    if x.size < 4:
        return math.nan, math.nan, "too few points"
    m, g = (x[1:] + x[:-1]) / 2, -np.diff(y) / np.diff(x)
    i = int(np.argmax(g))
    if i == 0 or i == g.size - 1:
        return math.nan, float(g[i]), "peak at the grid's edge"
    den = g[i - 1] - 2 * g[i] + g[i + 1]
    h = m[i + 1] - m[i]
    shift = 0.5 * h * (g[i - 1] - g[i + 1]) / den if den < 0 else 0.0
    return float(m[i] + shift), float(g[i]), "ok"


#: half-width of the fixed ν_f window about ν_½ over which the change of D is measured (one grid step)
WINDOW = 0.05


def _measures(x, y) -> tuple[float, float, float, float]:
    """(ν_½, ν_χ, W, window fraction) of one curve with no NaN; NaN where not defined. W = drop / largest
    −dy/dx and the window fraction (the fall of y across ν_½ ± WINDOW, linear interpolation, over the drop;
    1: the whole change inside the window) are given only with a crossing (a lower plateau), the window only
    when it lies on the grid."""
    c = half_crossing(x, y)[0]
    peak = slope_peak(x, y)[0]
    if not math.isfinite(c):
        return c, peak, math.nan, math.nan
    drop = y[0] - y.min()
    width = float(drop / np.max(-np.diff(y) / np.diff(x)))
    if c - WINDOW < x[0] or c + WINDOW > x[-1]:
        return c, peak, width, math.nan
    a, b = np.interp([c - WINDOW, c + WINDOW], x, y)
    return c, peak, width, float((a - b) / drop)


def locate(x, y, se, *, samples: int = 2000, seed: int = 1) -> dict:
    """Both locations, the width W and the window fraction of one D(ν_f) curve, each with its bootstrap σ
    (see the module text); NaN values (steps left out) are skipped.

    A value is reported (finite) only when the data themselves give one (status "ok"); its σ is over
    the draws that also give one, and ``found`` is that fraction of draws."""
    x, y, se = (np.asarray(a, dtype=float) for a in (x, y, se))
    ok = np.isfinite(y)
    x, y, se = x[ok], y[ok], np.nan_to_num(se[ok])
    rng = np.random.default_rng(seed)
    draws = y + se * rng.standard_normal((samples, y.size))
    boot = np.array([_measures(x, v) for v in draws]).reshape(samples, 4)
    data = _measures(x, y) if x.size >= 3 else (math.nan,) * 4
    status = {"half": half_crossing(x, y)[1], "peak": slope_peak(x, y)[2]}
    plateau = _lower_plateau(y)[0]
    if plateau is not None:     # a fall within 2σ of D's errors is no transition: no ν_½, W or window
        fall = y[0] - y[plateau].mean()
        fall_sigma = math.hypot(se[0], math.sqrt(np.sum(se[plateau] ** 2)) / plateau.sum())
        if not fall > 2 * fall_sigma:
            status["half"] = f"no drop beyond 2σ ({fall:.3g} ± {fall_sigma:.3g})"
            data = (math.nan, data[1], math.nan, math.nan)
    out = {}
    for k, name in enumerate(("half", "peak", "width", "window")):
        b = boot[:, k][np.isfinite(boot[:, k])]
        out[name] = {"value": data[k], "found": b.size / samples,
                     "sigma": float(b.std(ddof=1)) if b.size > 1 and math.isfinite(data[k]) else math.nan}
        if name in status:
            out[name]["status"] = status[name]
    g = grid_error(x, y) if x.size >= 3 and math.isfinite(data[0]) else math.nan
    if math.isfinite(g):     # ν_½: the draws' spread and the interpolation's error in quadrature
        out["half"].update(statistical=out["half"]["sigma"], grid=g, sigma=math.hypot(out["half"]["sigma"], g))
    out["drop"] = float(y[0] - y.min()) if y.size else math.nan
    out["max_slope"] = slope_peak(x, y)[1]
    return out


def location_fit(sizes, values, sigmas) -> dict:
    r"""ν_c(N) = ν_∞ + a/N by weighted least squares (a shift ∝ 1/volume, the form usually assumed at
    a first-order transition, with the chain's volume N: an assumption, not taken from a source read here); needs ≥ 3 sizes with σ > 0. Returns ν_∞, a, their σ,
    χ² and dof."""
    n, v, s = (np.asarray(a, dtype=float) for a in (sizes, values, sigmas))
    ok = np.isfinite(v) & (s > 0)
    n, v, s = n[ok], v[ok], s[ok]
    if n.size < 3:
        return {"sizes": n.tolist(), "points": int(n.size), "nu_inf": math.nan, "nu_inf_sigma": math.nan,
                "slope": math.nan, "slope_sigma": math.nan, "chi2": math.nan, "dof": 0}
    a = np.column_stack([np.ones_like(n), 1 / n]) / s[:, None]
    cov = np.linalg.inv(a.T @ a)
    p = cov @ a.T @ (v / s)
    chi2 = float(np.sum(((v - p[0] - p[1] / n) / s) ** 2))
    return {"sizes": n.tolist(), "points": int(n.size), "nu_inf": float(p[0]), "nu_inf_sigma": float(math.sqrt(cov[0, 0])),
            "slope": float(p[1]), "slope_sigma": float(math.sqrt(cov[1, 1])), "chi2": chi2, "dof": int(n.size - 2)}


def location_words(fit: dict, star: float, half: float = 0.5) -> tuple[str, str]:
    """(verdict, sentence) for ``location_fit``. Rules: fewer than 3 sizes or χ²/dof > 2 → undecided (the
    form does not carry the data); ν_∞ within 2σ of exactly one of ν_f* and 1/2 → approaches it; within
    2σ of both → undecided; of neither → approaches neither (ν_∞ printed)."""
    if fit["points"] < 3:
        return "undecided", f"only {fit['points']} sizes with a located transition: no fit"
    nu, s = fit["nu_inf"], fit["nu_inf_sigma"]
    r = fit["chi2"] / max(fit["dof"], 1)
    txt = (f"ν_∞ = {nu:.3f} ± {s:.3f}, a = {fit['slope']:.2f} ± {fit['slope_sigma']:.2f} (χ²/dof {r:.1f}), "
           f"N = {', '.join(str(int(x)) for x in fit['sizes'])}; ν_f* = {star:.4f}: {(nu - star) / s:+.1f}σ, "
           f"1/2: {(nu - half) / s:+.1f}σ")
    if r > 2:
        return "undecided", "ν_∞ + a/N does not fit the scatter: " + txt
    near_star, near_half = abs(nu - star) <= 2 * s, abs(nu - half) <= 2 * s
    if near_star and near_half:
        return "undecided", "compatible with both: " + txt
    if near_star:
        return "approaches ν_f*", "the lone-block threshold within 2σ, 1/2 excluded: " + txt
    if near_half:
        return "approaches 1/2", "the uniform mode's 1/2 within 2σ, ν_f* excluded: " + txt
    return "approaches neither", "both ν_f* and 1/2 beyond 2σ: " + txt
