"""Clauset–Shalizi–Newman fits of the chain report's own catalogs (the ``[catalog]`` and ``[near_half]``
sections; issue 17): goodness of fit by parametric bootstrap and likelihood ratios (``clauset.clauset_fit``),
read by the Clopper–Pearson rule of ``clauset.p_reading``.

A fit with B bootstrap samples costs seconds to minutes per catalog, more than a re-rendering should, so
each fit is kept in ``csn.json`` beside ``data.json``, keyed by a hash of the sizes fitted and of the fit's
settings: ``--from-data`` reads a fit whose key is there and computes (and adds) one whose key is not, so a
changed catalog can never be rendered with an old fit. tests/test_chain_report_csn.py recomputes entries
from the committed raw catalogs (``near_half.npz``, ``catalogs.npz``).

Sizes fitted: the potencies of the multi-block events (or patches) only: the 1-block events form an atom
at the lone block's closed-form potency (docs/chain.md "Threshold"), which is not a size distribution.
"""

from __future__ import annotations

import hashlib
import json
import math
from pathlib import Path

import numpy as np

from .clauset import p_reading, p_upper

__all__ = ["CSN_RULES", "CSN_SETTINGS", "CsnCache", "csn_cell", "csn_word"]

#: the fit settings of the report's own catalogs: B = 100 ("0 of 100" bounds p by 0.030 at 95 %)
CSN_SETTINGS = {"bootstrap": 100, "block_bootstrap": 100, "seed": 1, "resolution": 10}

#: the words of ``csn_word``, printed where the fits are shown
CSN_RULES = (
    "CSN (Clauset, Shalizi & Newman, SIAM Rev. 51, 661 (2009), through `powerlaw`: clauset.clauset_fit, x_min by "
    "least KS on a grid of 10 data values per decade) over the multi-block sizes: α of p(P) ∝ P^−α above x_min "
    "(b_P = α − 1) with its moving-block-bootstrap error; p from B = 100 parametric bootstrap samples, each refitted "
    "with its own x_min, so the null accounts for the fitting (unlike a KS distance against 1.36/√n); "
    "**ruled out** when the one-sided 95 % Clopper–Pearson bound on p is ≤ 0.1 (0 of 100 bounds it by 0.030), "
    "**plausible** when p > 0.1, **undecided** otherwise; **no scaling range** when the tail above x_min spans "
    "< 1 decade (largest / x_min < 10; not read as a power law whatever p); LR: the normalised log-likelihood "
    "ratio against the truncated power law (TPL), lognormal (LN) and exponential (exp), an alternative "
    "**favoured** when R < 0 with p < 0.1. The fits are seeded and deterministic on one machine (tests refit them "
    "exactly); on another CPU the last digits of α, x_min and R may move at rounding level, and a count k of B by one "
    "where a synthetic KS distance ties the data's")


def _key(values: np.ndarray, settings: dict) -> str:
    h = hashlib.sha256(np.ascontiguousarray(values, dtype="<f8").tobytes())
    h.update(json.dumps(settings, sort_keys=True).encode())
    return h.hexdigest()[:24]


def fit_dict(values, settings: dict = CSN_SETTINGS) -> dict:
    """clauset_fit of ``values`` as the JSON the cache keeps (every number the report prints from it)."""
    from .clauset import clauset_fit

    v = np.asarray(values, dtype=float)
    f = clauset_fit(v, **settings)
    return {"n": f.n, "n_tail": f.n_tail, "xmin": f.xmin, "alpha": f.alpha, "alpha_err": f.alpha_err,
            "alpha_block_err": f.alpha_block_err, "block": f.block, "ks": f.ks, "p": f.p_value,
            "bootstrap": f.bootstrap, "ratios": {k: list(r) for k, r in f.ratios.items()},
            "largest": float(v.max()), "decades": math.log10(float(v.max()) / f.xmin)}


class CsnCache:
    """``csn.json`` of a report directory: fits by key, computed on a miss and written back by ``save``."""

    def __init__(self, folder) -> None:
        self.path = Path(folder) / "csn.json"
        self.fits = json.loads(self.path.read_text()) if self.path.is_file() else {}
        self.used: set = set()
        self.changed = False

    def fit(self, values, settings: dict = CSN_SETTINGS) -> dict | None:
        """The fit of ``values`` (None below 20 values: too few for x_min and a tail)."""
        v = np.asarray(values, dtype=float)
        v = v[v > 0]
        if v.size < 20:
            return None
        k = _key(v, settings)
        if k not in self.fits:
            self.fits[k] = fit_dict(v, settings)
            self.changed = True
        self.used.add(k)
        return self.fits[k]

    def save(self) -> None:
        """Keep the fits this rendering used (others are stale), written only when something changed."""
        keep = {k: self.fits[k] for k in sorted(self.used)}
        if self.changed or keep.keys() != self.fits.keys():
            self.path.write_text(json.dumps(keep, indent=1, sort_keys=True) + "\n")
        self.fits = keep


def csn_word(f: dict | None, p_min: float = 0.1) -> str:
    """The reading of a fit by CSN_RULES: no fit, no scaling range, ruled out, undecided, plausible."""
    if not f:
        return "no fit"
    if f["decades"] < 1.0:
        return "no scaling range"
    return p_reading(f["p"], f["bootstrap"], p_min)


def favoured(f: dict | None, lr_p: float = 0.1) -> list:
    """The alternatives with R < 0 at p < lr_p (CSN_RULES)."""
    if not f:
        return []
    return [k for k, (r, p) in f["ratios"].items() if r < 0 and p < lr_p]


_SHORT = {"truncated_power_law": "TPL", "lognormal": "LN", "exponential": "exp"}


def csn_cell(f: dict | None) -> str:
    """One table cell: α ± err above x_min (n_tail, decades), p (k of B, 95 % bound), LR signs, the word."""
    if not f:
        return "fewer than 20 multi-block sizes"
    k = int(round(f["p"] * f["bootstrap"]))
    lr = ", ".join(f"{_SHORT[a]} {r:+.1f} (p {p:.2g})" for a, (r, p) in f["ratios"].items())
    return (f"α = {f['alpha']:.2f} ± {f['alpha_block_err']:.2f} above {f['xmin']:.3g} ({f['n_tail']} of {f['n']}, "
            f"{f['decades']:.1f} dec.); p = {f['p']:.2f} ({k} of {f['bootstrap']}, ≤ "
            f"{p_upper(f['p'], f['bootstrap']):.2g}); LR {lr}: **{csn_word(f)}**"
            + (f", favoured: {', '.join(_SHORT[a] for a in favoured(f))}" if favoured(f) else ""))
