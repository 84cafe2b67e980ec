"""Power-law statistics of event sizes by the method of Clauset, Shalizi and Newman, SIAM Rev. 51, 661
(2009), through the ``powerlaw`` package (Alstott, Bullmore and Plenz, PLoS ONE 9, e85777 (2014)).

* **Fit**: maximum likelihood for p(x) ∝ x^−α above x_min, x_min chosen by minimising the KS distance
  between the data above it and the fit (CSN Sec. 3.3; ``powerlaw.Fit``).
* **Goodness of fit**: the parametric bootstrap of CSN Sec. 4.1: synthetic samples of the same size,
  each value drawn with probability n_tail/n from the fitted power law above x_min and otherwise
  resampled from the observed values below x_min; each synthetic sample is fitted the same way
  (x_min search included) and p is the fraction whose KS distance is at least the data's. p ≤ 0.1
  rules the power law out (CSN's rule). ``bootstrap`` (default 50) trades accuracy for time: the
  error of p is about √(p(1 − p)/bootstrap) (CSN recommend ~2500 for ±0.01).
* **Alternatives**: the normalised log-likelihood ratio R and its p-value against the exponential,
  lognormal and truncated (tapered) power law, p(x) ∝ x^−α e^{−λx} (CSN Sec. 5; positive R favours
  the power law, p < 0.1 says the sign is significant; the truncated law is nested).
* **Serial correlation**: catalog events are not independent, so the MLE's error (α − 1)/√n_tail is
  too small. The moving-block bootstrap resamples blocks of ``block`` consecutive events (default
  ⌈n^{1/3}⌉) in catalog order and refits α at the fitted x_min (closed form); its standard deviation is
  the error given, and the ratio to the i.i.d. error says how much the correlation costs.

**b-values.** The fit gives the density exponent α; the cumulative count is N(≥ P) ∝ P^{−(α−1)}.
In potency units, with magnitude m = log10 P, N(≥ m) ∝ 10^{−b_P m}: **b_P = α − 1**. In moment
magnitude, seismic moment M0 = μ·P (rigidity times potency) and M_w = (2/3) log10 M0 + const
(Hanks and Kanamori, JGR 84, 2348 (1979)), so log10 P = 1.5 M_w + const and N(≥ M_w) ∝
10^{−1.5(α−1) M_w}: **b_M = 1.5 (α − 1) = 1.5 b_P**. The chain's "b" of earlier reports is b_P; a
seismological b ≈ 1 corresponds to b_P ≈ 2/3.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from ...errors import InputError

__all__ = ["p_reading", "p_upper", "ALTERNATIVES", "PowerLawFit", "clauset_fit"]

#: the alternatives of the likelihood-ratio tests (``powerlaw`` names)
ALTERNATIVES = ("exponential", "lognormal", "truncated_power_law")


def p_upper(p: float, bootstrap: int, confidence: float = 0.95) -> float:
    """One-sided Clopper–Pearson upper bound on the bootstrap p-value: k = round(p·B) of B synthetic samples
    were at least as far from their fit as the data. With k = 0 it is 1 − (1 − confidence)^(1/B): 0.26 for
    B = 10, so "0 of 10" does not show p ≤ 0.1. Bisection on the regularised incomplete beta (mpmath)."""
    import mpmath

    b = int(bootstrap)
    if b <= 0 or not math.isfinite(p):
        return math.nan
    k = int(round(p * b))
    if k >= b:
        return 1.0
    lo, hi = 0.0, 1.0
    for _ in range(60):     # P(X ≤ k | q) decreases in q: find q with P(X ≤ k) = 1 − confidence
        q = 0.5 * (lo + hi)
        tail = 1.0 - float(mpmath.betainc(k + 1, b - k, 0, q, regularized=True))   # P(X ≤ k), X ~ Bin(b, q)
        lo, hi = (q, hi) if tail > 1.0 - confidence else (lo, q)
    return hi


def p_reading(p: float, bootstrap: int, p_min: float = 0.1) -> str:
    """"ruled out" when even the 95 % upper bound on p is ≤ p_min; "plausible" when p > p_min; else
    "undecided" (the bootstrap's B cannot tell p from p_min)."""
    if not math.isfinite(p) or not bootstrap:
        return "untested"
    if p > p_min:
        return "plausible"
    return "ruled out" if p_upper(p, bootstrap) <= p_min else "undecided"


@dataclass(frozen=True)
class PowerLawFit:
    """A CSN power-law fit of one sample (see the module text for each number's meaning)."""

    n: int                  #: sample size
    n_tail: int             #: values ≥ x_min
    xmin: float
    alpha: float            #: density exponent, p(x) ∝ x^−α
    alpha_err: float        #: the MLE's i.i.d. error (α − 1)/√n_tail
    ks: float               #: KS distance of the fit above x_min
    p_value: float          #: parametric-bootstrap goodness of fit (NaN when bootstrap = 0)
    bootstrap: int          #: synthetic samples behind p_value
    #: per alternative: (R, p) of the normalised log-likelihood ratio (R > 0 favours the power law)
    ratios: dict = field(default_factory=dict)
    alpha_block_err: float = math.nan   #: moving-block-bootstrap error of α (NaN when not run)
    block: int = 0                      #: events per block of that bootstrap
    discrete: bool = False

    @property
    def b_potency(self) -> float:
        """b in potency units, N(≥ P) ∝ P^−b: α − 1."""
        return self.alpha - 1

    @property
    def b_magnitude(self) -> float:
        """b in moment-magnitude units: 1.5 (α − 1) (module text)."""
        return 1.5 * (self.alpha - 1)

    @property
    def alpha_error(self) -> float:
        """The error to quote: the block bootstrap's when it was run, else the i.i.d. one."""
        return self.alpha_block_err if math.isfinite(self.alpha_block_err) else self.alpha_err

    def verdict(self, p_min: float = 0.1, lr_p: float = 0.1) -> str:
        """CSN's reading in words: rejected (p ≤ p_min), or plausible, and which alternative the
        likelihood ratios favour with significance (p < lr_p)."""
        reading = p_reading(self.p_value, self.bootstrap, p_min)
        if reading == "untested":
            head = "not tested (no bootstrap)"
        elif reading == "ruled out":
            head = f"power law ruled out (p = {self.p_value:.2f}; ≤ {p_upper(self.p_value, self.bootstrap):.2g} at 95 %)"
        elif reading == "undecided":
            head = (f"power law undecided (p = {self.p_value:.2f} of {self.bootstrap} samples: ≤ "
                    f"{p_upper(self.p_value, self.bootstrap):.2g} at 95 %, not shown ≤ {p_min})")
        else:
            head = f"power law plausible (p = {self.p_value:.2f})"
        better = [k for k, (r, p) in self.ratios.items() if r < 0 and p < lr_p]
        worse = [k for k, (r, p) in self.ratios.items() if r > 0 and p < lr_p]
        parts = [head]
        if better:
            parts.append("favoured: " + ", ".join(better))
        if worse:
            parts.append("power law favoured over: " + ", ".join(worse))
        return "; ".join(parts)


def _fit(data, discrete: bool, xmin=None):
    import powerlaw

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")        # powerlaw warns on every edge case of its optimisers
        with np.errstate(all="ignore"):
            # powerlaw 2.0 bounds α to [0, 3] by default (DEFAULT_PARAMETER_RANGES): a steeper tail came
            # back as α = 3.000 exactly; [1, 20] covers every exponent of a normalisable tail seen here
            return powerlaw.Fit(data, discrete=discrete, xmin=xmin, verbose=False, parameter_ranges={"alpha": [1.0, 20.0]})


def _search(data, discrete: bool, xmin, resolution):
    """``powerlaw``'s fit; with ``resolution`` (and no fixed ``xmin``) x_min restricted to one data value
    per grid point, R per decade (``clauset_fit``), the least KS distance kept."""
    if resolution is None or xmin is not None:
        return _fit(data, discrete, xmin)
    v = np.unique(data)
    lo, hi = math.floor(math.log10(v[0]) * resolution), math.ceil(math.log10(v[-1]) * resolution)
    idx = np.unique(np.searchsorted(v, 10.0 ** (np.arange(lo, hi + 1) / resolution)))
    idx = idx[idx < max(1, v.size - 10)]          # leave ≥ 10 distinct values above the last candidate
    best = None
    for c in v[idx] if idx.size else v[:1]:
        f = _fit(data, discrete, float(c))
        d = float(f.power_law.D)
        if math.isfinite(d) and (best is None or d < best[0]):
            best = (d, f)
    return best[1] if best is not None else _fit(data, discrete, None)


def _pareto(rng, n: int, alpha: float, xmin: float, discrete: bool) -> np.ndarray:
    """n values of the power law above xmin (continuous: inverse transform; discrete: CSN's
    approximation ⌊(xmin − ½)(1 − u)^{−1/(α−1)} + ½⌋, their Eq. D.6)."""
    u = rng.random(n)
    if discrete:
        return np.floor((xmin - 0.5) * (1 - u) ** (-1 / (alpha - 1)) + 0.5)
    return xmin * (1 - u) ** (-1 / (alpha - 1))


def _alpha_at(x: np.ndarray, xmin: float, discrete: bool) -> float:
    """The MLE of α at a fixed x_min (continuous: CSN Eq. 3.1; discrete: their approximation Eq. 3.7)."""
    tail = x[x >= xmin]
    if tail.size == 0:
        return math.nan
    base = xmin - 0.5 if discrete else xmin
    s = np.sum(np.log(tail / base))
    return 1 + tail.size / s if s > 0 else math.nan


def clauset_fit(sizes, *, bootstrap: int = 50, block_bootstrap: int = 200, block: int | None = None,
                seed: int = 0, discrete: bool = False, xmin: float | None = None,
                alternatives: tuple = ALTERNATIVES, resolution: int | None = None) -> PowerLawFit:
    """Fit, test and compare a power law for ``sizes`` (event sizes in catalog order; values ≤ 0 are
    dropped: events without a member block under a velocity threshold have size 0).

    ``bootstrap`` synthetic samples for the goodness-of-fit p (0: not tested), ``block_bootstrap``
    resamples of blocks of ``block`` events for the error of α (0: not run), ``seed`` for both,
    ``discrete`` for integer sizes (blocks), ``xmin`` to fix x_min instead of searching it,
    ``alternatives`` the laws of the likelihood-ratio tests (a subset of ``ALTERNATIVES``; the
    discrete truncated law is slow to fit). ``resolution`` R (continuous sizes only): the x_min search
    (of the data and of each synthetic sample) tries only the smallest data value at or above each point
    of a geometric grid of R points per decade, each fitted by ``powerlaw`` at that fixed x_min, and
    keeps the one of least KS distance; ``powerlaw``'s own search tries every distinct value (each an
    O(n) fit), which 10^6-event catalogs cannot afford. The data are not changed; x_min is a data value,
    located to a factor 10^(1/R).
    """
    unknown = [a for a in alternatives if a not in ALTERNATIVES]
    if unknown:
        raise InputError("alternatives", unknown, "are not alternatives", f"use some of {list(ALTERNATIVES)}")
    x = np.asarray(sizes, dtype=float)
    if x.ndim != 1 or not np.all(np.isfinite(x)):
        raise InputError("sizes", "...", "must be a 1-d array of finite numbers", "drop NaN/inf values first")
    for name, value in (("bootstrap", bootstrap), ("block_bootstrap", block_bootstrap)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
            raise InputError(name, value, "is not a count", "give an integer ≥ 0 (0: skip)")
    x = x[x > 0]
    if resolution is not None:
        if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)) or resolution < 1 or discrete:
            raise InputError("resolution", resolution, "is not a grid of continuous sizes",
                             "give an integer ≥ 1 (points per decade) and discrete=False, or None")
    if x.size < 10:
        raise InputError("sizes", x.size, "are fewer than 10 positive values", "give a longer catalog")
    if block is not None and (isinstance(block, bool) or not isinstance(block, (int, np.integer)) or block < 1):
        raise InputError("block", block, "is not a block length", "give an integer ≥ 1, or None for ⌈n^(1/3)⌉")
    fit = _search(x, discrete, xmin, resolution)
    pl = fit.power_law
    alpha, x0, ks = float(pl.alpha), float(fit.xmin), float(pl.D)
    tail = x[x >= x0]
    n, n_tail = x.size, tail.size
    ratios = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with np.errstate(all="ignore"):
            for alt in alternatives:
                r, p = fit.distribution_compare("power_law", alt, normalized_ratio=True)
                ratios[alt] = (float(r), float(p))
    rng = np.random.default_rng(seed)
    p_value = math.nan
    if bootstrap:
        below = x[x < x0]
        hits = 0
        for _ in range(bootstrap):
            k = rng.binomial(n, n_tail / n) if below.size else n
            synth = np.concatenate((_pareto(rng, k, alpha, x0, discrete), rng.choice(below, n - k) if n > k else []))
            d = float(_search(synth, discrete, xmin, resolution).power_law.D)
            hits += d >= ks
        p_value = hits / bootstrap
    block_err, length = math.nan, 0
    if block_bootstrap:
        length = int(block) if block is not None else max(1, math.ceil(n ** (1 / 3)))
        starts_max = n - length + 1
        nblocks = math.ceil(n / length)
        alphas = []
        for _ in range(block_bootstrap):
            starts = rng.integers(0, starts_max, nblocks)
            idx = (starts[:, None] + np.arange(length)[None, :]).ravel()[:n]
            alphas.append(_alpha_at(x[idx], x0, discrete))
        alphas = np.asarray(alphas)
        block_err = float(np.std(alphas[np.isfinite(alphas)], ddof=1))
    return PowerLawFit(n=int(n), n_tail=int(n_tail), xmin=x0, alpha=alpha, alpha_err=(alpha - 1) / math.sqrt(n_tail),
                       ks=ks, p_value=p_value, bootstrap=int(bootstrap), ratios=ratios, alpha_block_err=block_err,
                       block=length, discrete=discrete)
