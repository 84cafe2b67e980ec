"""Size of the largest events of a chain catalog and its growth with N: the moment-ratio cutoff, the
tapered Gutenberg–Richter law, and the reading of both as critical-like or characteristic-size.

Potency P of an event (docs/chain.md), magnitude m = log10 P, so a Gutenberg–Richter law
N(≥ m) ∝ 10^{−bm} is a Pareto law N(≥ P) ∝ P^{−b} (docs/chain.md, "Cutoff and finite-size scaling").
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["MERGED", "mfd_reading", "moment_cutoff", "slip_clusters", "tapered_gr"]

#: slipping fraction above which a catalog's events are read as merged slips (``mfd_reading``)
MERGED = 0.5


def slip_clusters(slip, periodic: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """The connected slip patches of one event: (blocks, potency) per run of adjacent blocks with slip > 0.

    ``slip`` is U_j(end) − U_j(start) of the event, per block. Two patches separated by a block that did
    not move were two slips that never interacted through the chain's springs inside the event (a
    stuck block transmits no slip), though the catalog counts them as one event because the chain
    was never all stuck in between. With ``periodic`` ends a patch touching both ends is one patch.
    Patches are in the order of their first block (a wrapped one first).
    """
    s = np.asarray(slip, dtype=float)
    moved = s > 0
    if not moved.any():
        return np.zeros(0, dtype=np.int64), np.zeros(0)
    if periodic and moved.all():
        return np.array([s.size]), np.array([s.sum()])
    shift = 0
    if periodic and moved[0] and moved[-1]:      # start after the last block that did not move: the wrapped patch is first
        shift = int(np.flatnonzero(~moved)[-1]) + 1
        s, moved = np.roll(s, -shift), np.roll(moved, -shift)
    edge = np.diff(np.concatenate(([False], moved, [False])).astype(np.int8))
    starts, ends = np.flatnonzero(edge == 1), np.flatnonzero(edge == -1)
    sums = np.array([s[a:b].sum() for a, b in zip(starts, ends)])
    return (ends - starts).astype(np.int64), sums


def moment_cutoff(potency, batches: int = 10) -> dict:
    r"""The cutoff potency P_c = ⟨P²⟩/⟨P⟩ and the mean ⟨P⟩, with errors by batch means.

    For a size distribution p(P) = P^{−τ} G(P/P_ξ) with 1 < τ < 2 above a fixed lower cut, both
    moments are dominated by the cutoff, ⟨P²⟩ ∝ P_ξ^{3−τ} and ⟨P⟩ ∝ P_ξ^{2−τ}, so

    .. math:: P_c = \langle P^2\rangle / \langle P\rangle \propto P_\xi

    whatever τ and G (the usual finite-size-scaling estimator of the characteristic size, e.g.
    Christensen & Moloney, *Complexity and Criticality*, 2005, §3.9); for a distribution with a
    characteristic size it is of the order of that size. Events of a chain catalog are correlated,
    so σ comes from ``batches`` consecutive parts of the catalog: σ = sd(batch values)/√batches.
    Fewer than 2 events per batch give NaN errors.
    """
    p = np.asarray(potency, dtype=float)
    out = {"n": int(p.size), "batches": int(batches)}
    if p.size == 0:
        return {**out, "mean": math.nan, "mean_sigma": math.nan, "cutoff": math.nan, "cutoff_sigma": math.nan}
    out.update(mean=float(p.mean()), cutoff=float((p * p).mean() / p.mean()))
    if p.size < 2 * batches or batches < 2:
        return {**out, "mean_sigma": math.nan, "cutoff_sigma": math.nan}
    parts = np.array_split(p, batches)
    means = np.array([q.mean() for q in parts])
    cuts = np.array([(q * q).mean() / q.mean() for q in parts])
    return {**out, "mean_sigma": float(means.std(ddof=1) / math.sqrt(batches)),
            "cutoff_sigma": float(cuts.std(ddof=1) / math.sqrt(batches))}


def tapered_gr(potency, p_min: float) -> dict:
    r"""Maximum-likelihood fit of the tapered Gutenberg–Richter (tapered Pareto) law above ``p_min``.

    Survival function (Kagan, Geophys. J. Int. 148, 520 (2002)), P ≥ a = ``p_min``:

    .. math:: S(P) = (P/a)^{-b}\, e^{-\gamma (P - a)}, \qquad
              \ln L = \sum_i \ln(b + \gamma P_i) - \sum_i \ln P_i - b \sum_i \ln(P_i/a) - \gamma \sum_i (P_i - a),

    with γ = 1/P_corner. b > 0, γ = 0 is a pure power law (no cutoff within the data); b = 0, γ > 0
    an exponential law with a characteristic size 1/γ. ln L is concave in (b, γ), so the maximum
    over b, γ ≥ 0 is unique: for each γ, b̂(γ) solves Σ 1/(b + γP_i) = Σ ln(P_i/a) (Newton; or b̂ = 0),
    and γ̂ is where the profile's slope Σ P_i/(b̂ + γP_i) − Σ(P_i − a) changes sign (bisection on
    [0, n/Σ(P_i − a)], beyond which the slope is negative). Errors from the observed information
    matrix [[Σ w⁻², Σ P w⁻²], [Σ P w⁻², Σ P² w⁻²]], w = b + γP. Also returned: the KS distance of
    the sample to the fitted law with the 5 % value 1.36/√n (parameters estimated: conservative),
    and 2Δln L against the pure power law (γ = 0), χ²₁ under it (3.84 at 5 %).
    """
    p = np.asarray(potency, dtype=float)
    p = np.sort(p[p >= p_min])
    n = p.size
    out = {"p_min": float(p_min), "n": int(n)}
    nan = dict(b=math.nan, b_sigma=math.nan, gamma=math.nan, gamma_sigma=math.nan, corner=math.nan,
               corner_sigma=math.nan, ks=math.nan, ks_crit=math.nan, lr=math.nan)
    if n < 10 or p[-1] <= p_min:
        return {**out, **nan}
    x = p / p_min                 # dimensionless: a = 1
    lsum, qsum = float(np.log(x).sum()), float((x - 1).sum())

    def b_of(g):
        if g == 0:
            return n / lsum
        if float(np.sum(1 / (g * x))) <= lsum:
            return 0.0
        # f(b) = Σ 1/(b + γx) − Σ ln x is convex and decreasing: Newton from b = 0 (f > 0) rises
        # monotonically to the root without overshooting
        b = 0.0
        for _ in range(100):
            w = 1 / (b + g * x)
            step = (float(w.sum()) - lsum) / float((w * w).sum())
            b += step
            if step <= 1e-15 * b:
                break
        return b

    def slope(g):
        b = b_of(g)
        return float(np.sum(x / (b + g * x))) - qsum, b

    s0, b0 = slope(0.0)
    if s0 <= 0:
        g, b = 0.0, b0
    else:
        lo, hi = 0.0, n / qsum
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if slope(mid)[0] > 0:
                lo = mid
            else:
                hi = mid
            if hi - lo <= 1e-10 * hi:     # far below σ_γ
                break
        g = 0.5 * (lo + hi)
        b = b_of(g)
    w = b + g * x
    info = np.array([[np.sum(w**-2), np.sum(x * w**-2)], [np.sum(x * w**-2), np.sum(x * x * w**-2)]])
    cov = np.linalg.inv(info)
    sb, sg = math.sqrt(cov[0, 0]), math.sqrt(cov[1, 1])
    gamma, gamma_sigma = g / p_min, sg / p_min

    def loglik(bb, gg):
        return float(np.sum(np.log(bb + gg * x)) - bb * lsum - gg * qsum)

    cdf = 1 - x ** (-b) * np.exp(-g * (x - 1))
    i = np.arange(1, n + 1)
    ks = float(max(np.max(i / n - cdf), np.max(cdf - (i - 1) / n)))
    corner = 1 / gamma if gamma > 0 else math.inf
    return {**out, "b": float(b), "b_sigma": sb, "gamma": gamma, "gamma_sigma": gamma_sigma, "corner": corner,
            "corner_sigma": gamma_sigma / gamma**2 if gamma > 0 else math.nan,
            "ks": ks, "ks_crit": 1.36 / math.sqrt(n), "lr": 2 * (loglik(b, g) - loglik(b0, 0.0))}


#: the reason ``mfd_reading`` gives when the CSN test finds no power-law stretch at some N
_NO_STRETCH = "no CSN power-law stretch at some N"


def _power_stretch(r) -> bool:
    """A power law plausible over ≥ 1 decade by CSN; without ``csn``, the tapered law's KS."""
    if "csn" not in r:
        return r["tapered"]["ks"] <= r["tapered"]["ks_crit"]
    f = r["csn"]
    if not f:
        return False         # fewer than 20 sizes: nothing to test
    from ._study_csn import csn_word

    # (a truncated power law favoured by the likelihood ratio is only better than the pure one, not shown to fit:
    # the CSN bootstrap tests the pure law alone, so only "plausible" counts)
    return csn_word(f) == "plausible"


def mfd_reading(rows: list, cutoff_fss: dict, spanning_fss: dict) -> tuple[str, str]:
    """(word, reason) for the magnitude–frequency distributions of one ν_f over several N.

    ``rows``: per N (ascending) a dict with ``n``, ``tapered`` (``tapered_gr``), ``spanning_excess``
    (observed/GR-extrapolated system-spanning events, NaN when none) and optionally ``slip_fraction``
    (Σ duration / elapsed time of the catalog). ``cutoff_fss``/``spanning_fss``:
    ``analysis.finite_size_fit`` of the cutoff potency and of the spanning fraction against N
    (θ < 0: grows). Rules, from the two pictures (docs/chain.md, "Cutoff and finite-size scaling"):

    * **critical-like**: the cutoff grows with N (θ < −2σ), at every N the sizes have a power-law
      stretch by Clauset–Shalizi–Newman (a row's ``csn``, ``_study_csn``: ≥ 1 decade above x_min and the
      power law plausible by its bootstrap p; rows without ``csn`` fall back on the tapered law's KS
      distance against 1.36/√n, which ignores that the parameters were fitted),
      its b is > 2σ above 0 at every N and the b of the largest N is within 2σ of the smallest N's,
      and no N has a spanning excess above 3;
    * **characteristic-size** (first-order-like): at the largest N, b is within 2σ of 0 (an
      exponential law: a size scale, not a power law), or the spanning events exceed the power law's
      extrapolation more than 3-fold while the spanning fraction does not decrease with N
      (θ ≤ 2σ);
    * **undecided** otherwise, or with fewer than 3 sizes holding a fit, or when at some N the
      slipping fraction exceeds ``MERGED`` (the chain is all stuck less than half of the time: a
      catalogued event, which ends only when every block is stuck, then sums separate slips, and
      its size measures the merging, not a rupture); the reason says which test failed.
    """
    fitted = [r for r in rows if math.isfinite(r["tapered"]["b"])]
    if len(fitted) < 3 or not math.isfinite(cutoff_fss.get("theta", math.nan)):
        return "undecided", f"only {len(fitted)} sizes with a fit of ≥ 10 events"
    merged = [r for r in fitted if r.get("slip_fraction", 0.0) > MERGED]
    if merged:
        return "undecided", ("events merge: some block slips during " + ", ".join(
            f"{100 * r['slip_fraction']:.0f} % (N = {r['n']})" for r in merged) + " of the time")
    big, small = fitted[-1], fitted[0]
    tb, ts = big["tapered"], small["tapered"]
    grows = cutoff_fss["theta"] < -2 * cutoff_fss["theta_sigma"]
    ks_ok = all(_power_stretch(r) for r in fitted)
    b_pos = all(r["tapered"]["b"] > 2 * r["tapered"]["b_sigma"] for r in fitted)
    b_same = abs(tb["b"] - ts["b"]) <= 2 * math.hypot(tb["b_sigma"], ts["b_sigma"])
    excess = [r["n"] for r in fitted if math.isfinite(r["spanning_excess"]) and r["spanning_excess"] > 3]
    span_th, span_s = spanning_fss.get("theta", math.nan), spanning_fss.get("theta_sigma", math.nan)
    span_stays = math.isfinite(span_th) and span_th <= 2 * span_s
    if grows and ks_ok and b_pos and b_same and not excess:
        return "critical-like", (f"cutoff ∝ N^{-cutoff_fss['theta']:.2f}±{cutoff_fss['theta_sigma']:.2f}, "
                                 f"power-law stretch at every N, tapered b = {ts['b']:.2f} ± {ts['b_sigma']:.2f} (N = "
                                 f"{small['n']}) and {tb['b']:.2f} ± {tb['b_sigma']:.2f} (N = {big['n']})")
    if tb["b"] <= 2 * tb["b_sigma"]:
        return "characteristic-size", (f"at N = {big['n']} the tapered fit has b = {tb['b']:.2f} ± {tb['b_sigma']:.2f}: "
                                       f"an exponential law with a size scale P ≈ {tb['corner']:.3g}")
    if big["n"] in excess and span_stays:
        return "characteristic-size", (f"spanning events {big['spanning_excess']:.3g}× the power law's extrapolation at "
                                       f"N = {big['n']}, spanning fraction ∝ N^{-span_th:.2f}±{span_s:.2f}")
    failed = [w for w, ok in (("cutoff does not grow beyond 2σ", grows), (_NO_STRETCH if any("csn" in r for r in fitted) else
                                                                  "KS rejects the tapered law at some N", ks_ok),
                              ("b within 2σ of 0 at some N", b_pos), ("b changes with N", b_same),
                              ("spanning excess > 3 at N = " + ", ".join(map(str, excess)), not excess)) if not ok]
    return "undecided", "; ".join(failed) or "no rule applies"
