"""Statistics of chain catalogs: magnitude–frequency, b-value, system-spanning events, recurrence,
and the order parameter of a ν_f sweep within one run (hysteresis loops).

Magnitude m = log10 P (P the potency of an event, docs/chain.md).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["b_value", "finite_size_fit", "hysteresis", "magnitude_frequency", "recurrence", "spanning_excess",
           "sweep_nu_f"]

_LOG10E = math.log10(math.e)


def magnitude_frequency(potency, per_decade: int = 10) -> dict:
    """Log-binned counts and summed potency: bin edges in m = log10 P, ``per_decade`` bins per decade."""
    m = np.log10(np.asarray(potency, dtype=float))
    lo, hi = math.floor(m.min() * per_decade) / per_decade, math.ceil(m.max() * per_decade) / per_decade + 1e-9
    edges = np.arange(lo, hi + 1 / per_decade, 1 / per_decade)
    counts, _ = np.histogram(m, edges)
    moment, _ = np.histogram(m, edges, weights=np.asarray(potency, dtype=float))
    return {"edges": edges, "counts": counts, "potency": moment}


def b_value(potency, *, m_min: float | None = None, m_max: float | None = None) -> dict:
    r"""Maximum-likelihood b-value for continuous magnitudes m = log10 P on [m_min, m_max].

    Without an upper cut, Aki's estimator (Aki, Bull. Earthq. Res. Inst. 43, 237 (1965)):

    .. math:: \hat b = \frac{\log_{10} e}{\bar m - m_{min}}, \qquad \sigma_b = \hat b/\sqrt{n}.

    With ``m_max`` (here: below the system-spanning events, whose excess is measured apart) the
    magnitudes follow an exponential truncated at Δ = m_max − m_min, and the likelihood equation for
    β = b ln 10 (Page, Bull. Seismol. Soc. Am. 58, 1131 (1968)) is

    .. math:: \bar m - m_{min} = \frac{1}{\beta} - \frac{\Delta e^{-\beta\Delta}}{1 - e^{-\beta\Delta}},

    solved by bisection; σ_β from the Fisher information
    n [1/β² − Δ² e^{−βΔ}/(1 − e^{−βΔ})²]. Aki's formula on a truncated sample is biased high.
    ``m_min`` defaults to the 10th percentile of m. Fewer than 10 magnitudes, or a mean at or above
    the middle of the range (no decreasing exponential fits), give NaN.
    """
    m = np.log10(np.asarray(potency, dtype=float))
    if m_min is None:
        m_min = float(np.percentile(m, 10))
    sel = m[(m >= m_min) & (m <= (np.inf if m_max is None else m_max))]
    n = sel.size
    out = {"m_min": float(m_min), "m_max": None if m_max is None else float(m_max), "n": int(n)}
    mean = float(sel.mean()) - m_min if n else math.nan
    if n < 10 or not mean > 0:
        return {"b": math.nan, "sigma": math.nan, **out}
    if m_max is None:
        b = _LOG10E / mean
        return {"b": float(b), "sigma": float(b / math.sqrt(n)), **out}
    width = m_max - m_min
    if mean >= width / 2:
        return {"b": math.nan, "sigma": math.nan, **out}
    lo, hi = 1e-9 / width, 1.0 / mean          # the mean decreases from Δ/2 (β → 0) to 0 (β → ∞)
    while hi - lo > 1e-13 * hi:
        beta = 0.5 * (lo + hi)
        if _truncated_mean(beta, width) > mean:
            lo = beta
        else:
            hi = beta
    beta = 0.5 * (lo + hi)
    e = math.exp(-beta * width)
    info = n * (1 / beta**2 - width**2 * e / (1 - e) ** 2)
    return {"b": beta * _LOG10E, "sigma": _LOG10E / math.sqrt(info), **out}


def _truncated_mean(beta: float, width: float) -> float:
    """Mean of an exponential of rate β truncated to [0, width]."""
    e = math.exp(-beta * width)
    return 1 / beta - width * e / (1 - e)


def spanning_excess(potency, n_blocks, n: int, fit: dict) -> dict:
    """System-spanning events (n_blocks = N) observed, against the Gutenberg–Richter extrapolation
    N(≥ m) = n_fit 10^{−b(m − m_min)} of the fit at the smallest spanning magnitude."""
    potency = np.asarray(potency, dtype=float)
    span = np.asarray(n_blocks) == n
    observed = int(span.sum())
    if observed == 0 or not math.isfinite(fit["b"]):
        return {"spanning": observed, "fraction": observed / potency.size, "expected": math.nan, "excess": math.nan}
    m_span = float(np.log10(potency[span]).min())
    expected = fit["n"] * 10 ** (-fit["b"] * (m_span - fit["m_min"]))
    return {"spanning": observed, "fraction": observed / potency.size, "expected": float(expected),
            "excess": float(observed / expected) if expected > 0 else math.inf, "m_spanning_min": m_span}


def recurrence(t_start, mask) -> dict:
    """Inter-event times of the selected (large) events: mean and coefficient of variation."""
    t = np.asarray(t_start, dtype=float)[np.asarray(mask)]
    if t.size < 3:
        return {"count": int(t.size), "mean": math.nan, "cv": math.nan}
    dt = np.diff(t)
    return {"count": int(t.size), "mean": float(dt.mean()), "cv": float(dt.std() / dt.mean())}


def sweep_nu_f(law, *, n: int, ell: float, nu: float, nu_f_values, cycles_per_step: float = 3.0,
               max_events_per_step: int = 200_000, transient_cycles: float | None = None, ends: str = "free",
               amplitude: float = 0.1, seed: int = 1, spanning_fraction: float = 1.0, sigma: float = 0.0) -> dict:
    r"""ν_f changed in steps within one run (no restart between steps), each step ``cycles_per_step``
    loading cycles long: events are run until the driver has advanced by ν ΔT ≥ ``cycles_per_step``
    units of slip per block (or ``max_events_per_step`` events; ``cycles`` says what was reached).

    Per step, with ΔT the time from the end of the step's last event before to the end of its last
    event (loading included):

    * Ψ = Σ_{spanning} P / (N ν ΔT): the slip per block per unit of driver slip carried by events
      that involve at least ``spanning_fraction``·N blocks (→ 1 when the chain moves as one);
    * D = Σ P / Σ n_blocks: the mean slip of a block in an event it takes part in. For N = 1 it is
      the single block's Δ, the seed's order parameter; as ν → 0 it stays O(1) in stick-slip and is
      O(ν) in creep (docs/chain.md, "Order parameter");
    * closure = Σ P / (N ν ΔT): 1 in a steady state, off by the stress stored or released during the
      step, of order (largest event's P)/(N ν ΔT);
    * slip_fraction = Σ duration / ΔT, the fraction of the step's time during which some block slips,
      and longest_event = ν · (longest duration), in loading cycles. Events are separated only while
      slip_fraction ≪ 1: as N ν grows the chain is rarely all stuck, one "event" merges many slips
      (or the whole chain slides for cycles), and D then measures the merged event, not a block's slip;
    * events, cycles = ν ΔT, mean n_blocks, status.

    A transient of ``transient_cycles`` (default: one step) at the first ν_f is run first and
    discarded (the random start). ``sigma``: the friction drop (docs/chain.md, "Friction drop").
    """
    from ...laws import resolve_law
    from ._loop import ChainLoop
    from ._validate import check_initial

    u0 = check_initial(n, ell, ends, None, amplitude, seed)
    loop = ChainLoop(resolve_law(law), n, ell, nu, float(nu_f_values[0]), ends, u0, drop=sigma)
    threshold = math.ceil(spanning_fraction * n)
    keys = ("psi", "slip_per_block", "closure", "slip_fraction", "longest_event", "events", "cycles", "mean_n_blocks",
            "status")
    out = {k: [] for k in keys}

    def step(cycles):
        t0, p, nb, dur, status = float(loop.t), [], [], [], "complete"
        while nu * (float(loop.t) - t0) < cycles and len(p) < max_events_per_step:
            r = loop.run(1)
            p += [float(x) for x in r["catalog"]["potency"]]
            nb += list(r["catalog"]["n_blocks"])
            dur += [float(x) for x in r["catalog"]["duration"]]
            if str(r["status"]) != "complete":
                status = str(r["status"])
                break
        return np.array(p), np.array(nb, dtype=np.int64), np.array(dur), float(loop.t) - t0, status

    step(cycles_per_step if transient_cycles is None else transient_cycles)
    for nf in nu_f_values:
        loop.nu_f = loop.dtype(nf)
        p, nb, dur, dt, status = step(cycles_per_step)
        load = n * nu * dt
        out["psi"].append(float(p[nb >= threshold].sum() / load) if dt > 0 else math.nan)
        out["slip_per_block"].append(float(p.sum() / nb.sum()) if nb.size else math.nan)
        out["closure"].append(float(p.sum() / load) if dt > 0 else math.nan)
        out["slip_fraction"].append(float(dur.sum() / dt) if dt > 0 else math.nan)
        out["longest_event"].append(nu * float(dur.max()) if dur.size else math.nan)
        out["events"].append(int(p.size))
        out["cycles"].append(nu * dt)
        out["mean_n_blocks"].append(float(nb.mean()) if nb.size else math.nan)
        out["status"].append(status)
    return {"nu_f": list(map(float, nu_f_values)), **out}


def hysteresis(nu_f_up, up, down, se_up, se_down) -> dict:
    r"""Jump and loop of an order parameter measured with ν_f going up, then down over the same values.

    ``up``/``down`` (and their standard errors) are aligned with ``nu_f_up`` (ascending). Returns

    * jump: the largest change |x_{i+1} − x_i| between neighbouring ν_f on the up branch, its sign,
      place and σ = √(se_i² + se_{i+1}²) (on a grid it is bounded by the grid: a continuous curve
      gives a jump that shrinks with the spacing, a discontinuous one does not);
    * width: max_i |up_i − down_i| and its σ (the maximum of noisy differences is biased upwards,
      by about one σ when no loop is there);
    * area: Σ_i (down_i − up_i) w_i with trapezoid weights w_i, and its σ (signed, not biased).

    NaN values (steps left out) are skipped; all NaN gives NaN.
    """
    x = np.asarray(nu_f_up, dtype=float)
    up, down = np.asarray(up, dtype=float), np.asarray(down, dtype=float)
    su, sd = np.asarray(se_up, dtype=float), np.asarray(se_down, dtype=float)
    d = np.diff(up)
    diff = down - up
    if np.all(np.isnan(d)) or np.all(np.isnan(diff)):
        return {k: math.nan for k in ("jump", "jump_sign", "jump_sigma", "width", "width_sigma", "width_at",
                                      "area", "area_sigma")} | {"jump_at": [math.nan, math.nan]}
    i = int(np.nanargmax(np.abs(d)))
    j = int(np.nanargmax(np.abs(diff)))
    w = np.zeros_like(x)
    w[:-1] += np.diff(x) / 2
    w[1:] += np.diff(x) / 2
    return {"jump": float(abs(d[i])), "jump_sign": float(np.sign(d[i])), "jump_sigma": float(math.hypot(su[i], su[i + 1])),
            "jump_at": [float(x[i]), float(x[i + 1])],
            "width": float(abs(diff[j])), "width_sigma": float(math.hypot(su[j], sd[j])), "width_at": float(x[j]),
            "area": float(np.nansum(w * diff)), "area_sigma": float(math.sqrt(np.nansum(w**2 * (su**2 + sd**2))))}


def finite_size_fit(sizes, values, sigmas) -> dict:
    r"""Finite-size scaling of a jump or loop width: y(N) = A N^{−θ} against y(N) = y_∞.

    The power law is fitted by weighted least squares on ln y (σ_{ln y} = σ_y/y, points with y ≤ 0 or
    σ ≤ 0 left out):

    .. math:: \hat\theta = -\frac{S\,S_{xy} - S_x S_y}{S\,S_{xx} - S_x^2},\qquad
              \sigma_\theta^2 = \frac{S}{S\,S_{xx} - S_x^2},

    x = ln N, sums weighted by 1/σ²_{ln y}; the constant by the weighted mean. θ > 0 beyond its error
    means the quantity vanishes as N grows (a transition that turns continuous); θ compatible with 0
    and an acceptable constant fit means it persists; both fits acceptable means the data cannot tell.
    χ² and degrees of freedom are returned for both.
    """
    n, y, s = (np.asarray(a, dtype=float) for a in (sizes, values, sigmas))
    ok = (y > 0) & (s > 0) & np.isfinite(y) & np.isfinite(s)
    n, y, s = n[ok], y[ok], s[ok]
    out = {"sizes": n.tolist(), "points": int(n.size)}
    if n.size < 2:
        return {**out, "theta": math.nan, "theta_sigma": math.nan, "amplitude": math.nan,
                "chi2_power": math.nan, "dof_power": 0, "constant": math.nan, "constant_sigma": math.nan,
                "chi2_constant": math.nan, "dof_constant": 0}
    x, ly, w = np.log(n), np.log(y), (y / s) ** 2
    S, Sx, Sy, Sxx, Sxy = w.sum(), (w * x).sum(), (w * ly).sum(), (w * x * x).sum(), (w * x * ly).sum()
    det = S * Sxx - Sx**2
    slope, icpt = (S * Sxy - Sx * Sy) / det, (Sxx * Sy - Sx * Sxy) / det
    chi2_pl = float(np.sum(w * (ly - icpt - slope * x) ** 2))
    wc = 1 / s**2
    c = float(np.sum(wc * y) / wc.sum())
    chi2_c = float(np.sum(wc * (y - c) ** 2))
    return {**out, "theta": float(-slope), "theta_sigma": float(math.sqrt(S / det)), "amplitude": float(math.exp(icpt)),
            "chi2_power": chi2_pl, "dof_power": int(n.size - 2), "constant": c,
            "constant_sigma": float(1 / math.sqrt(wc.sum())), "chi2_constant": chi2_c, "dof_constant": int(n.size - 1)}
