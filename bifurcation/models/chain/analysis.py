"""Statistics of chain catalogs: magnitude–frequency, b-value, system-spanning events, recurrence,
and the order parameter of a ν_f sweep within one run (hysteresis loops).

Magnitude m = log10 P (P the potency of an event, docs/chain.md).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["b_value", "magnitude_frequency", "recurrence", "spanning_excess", "sweep_nu_f"]

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
    r"""Aki–Utsu maximum-likelihood b-value for continuous magnitudes m = log10 P on [m_min, m_max].

    .. math:: \hat b = \frac{\log_{10} e}{\bar m - m_{min}}, \qquad \sigma_b = \hat b/\sqrt{n}

    (Aki, Bull. Earthq. Res. Inst. 43, 237 (1965); the upper cut ``m_max`` excludes the system-spanning
    events, whose excess is measured apart). ``m_min`` defaults to the 10th percentile of m.
    """
    m = np.log10(np.asarray(potency, dtype=float))
    if m_min is None:
        m_min = float(np.percentile(m, 10))
    sel = m[(m >= m_min) & (m <= (np.inf if m_max is None else m_max))]
    n = sel.size
    if n < 10 or sel.mean() <= m_min:
        return {"b": math.nan, "sigma": math.nan, "m_min": m_min, "m_max": m_max, "n": int(n)}
    b = _LOG10E / (sel.mean() - m_min)
    return {"b": float(b), "sigma": float(b / math.sqrt(n)), "m_min": float(m_min),
            "m_max": None if m_max is None else float(m_max), "n": int(n)}


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


def sweep_nu_f(law, *, n: int, ell: float, nu: float, nu_f_values, events_per_step: int, ends: str = "free",
               amplitude: float = 0.1, seed: int = 1, spanning_fraction: float = 1.0) -> dict:
    """ν_f changed in steps within one run (no restart between steps); per step the order parameter

        Ψ = Σ_{spanning events} P / (N ν ΔT),

    the fraction of the long-run slip (N ν per unit time) released by events that involve at least
    ``spanning_fraction``·N blocks, ΔT the time covered by the step's events (from the first start to
    the end of the last event). Ψ → 1 when the chain moves as one (stick-slip), → 0 when it slips
    in small events or creeps. ``events_per_step`` events at the first ν_f are run first and
    discarded (the transient from the random start). With k events per step Ψ carries an O(1/k)
    error from the loading time left over from the step before.
    """
    from ...laws import resolve_law
    from ._loop import ChainLoop
    from ._validate import check_initial

    u0 = check_initial(n, ell, ends, None, amplitude, seed)
    loop = ChainLoop(resolve_law(law), n, ell, nu, float(nu_f_values[0]), ends, u0)
    loop.run(events_per_step)     # the transient from the random start is not part of the loop
    psi, mean_size, statuses = [], [], []
    threshold = math.ceil(spanning_fraction * n)
    for nf in nu_f_values:
        loop.nu_f = loop.dtype(nf)
        t0 = float(loop.t)
        out = loop.run(events_per_step)
        cat = out["catalog"]
        statuses.append(str(out["status"]))
        p = np.array([float(x) for x in cat["potency"]])
        nb = np.array(cat["n_blocks"])
        span_t = float(loop.t) - t0
        psi.append(float(p[nb >= threshold].sum() / (n * nu * span_t)) if span_t > 0 else math.nan)
        mean_size.append(float(nb.mean()) if nb.size else math.nan)
    return {"nu_f": list(map(float, nu_f_values)), "psi": psi, "mean_n_blocks": mean_size, "status": statuses}
