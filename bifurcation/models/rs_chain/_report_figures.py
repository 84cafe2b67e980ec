"""The figures of the rate-and-state chain's store section (``store_report.blocks``).

Each function takes arrays read from the store and returns a matplotlib ``Figure`` on the report's
Agg canvas; ``report.figures.save`` writes it without date or software tag, so the same store gives
the same PNG bytes with the same matplotlib and FreeType.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["BINS_PER_DECADE", "figure_balance", "figure_sizes", "figure_space_time", "log_binned_density"]

#: Bins of the size density per decade of potency (edges at 10^(j/5): a fixed grid, not data-dependent).
BINS_PER_DECADE = 5
_MARKERS = ("o", "s", "^", "v", "D", "P")


def log_binned_density(sizes, n_total: int):
    """(centres, density, counts) of the positive ``sizes`` in bins of 1/``BINS_PER_DECADE`` decade:
    counts / (n_total · bin width), the probability density p(P) (bins with no event are left out)."""
    x = np.asarray(sizes, dtype=float)
    x = x[x > 0]
    if x.size == 0:
        return np.empty(0), np.empty(0), np.empty(0, dtype=int)
    lo = math.floor(math.log10(x.min()) * BINS_PER_DECADE)
    hi = math.floor(math.log10(x.max()) * BINS_PER_DECADE) + 1
    edges = 10.0 ** (np.arange(lo, hi + 1) / BINS_PER_DECADE)
    counts, _ = np.histogram(x, edges)
    keep = counts > 0
    centres = np.sqrt(edges[:-1] * edges[1:])
    return centres[keep], counts[keep] / (n_total * np.diff(edges)[keep]), counts[keep]


def figure_sizes(curves):
    """The potency density per run (points) and its Clauset fit above x_min (line).

    ``curves``: (label, kept sizes, fit or None) per run; the fitted density is the power law scaled by
    the share of the kept events above x_min: (n_tail/n)(α − 1)/x_min (P/x_min)^−α.
    """
    from ...report import figures as F

    fig, axes = F._figure(5.8, 4.2)
    ax = axes[0][0]
    for k, (label, sizes, fit) in enumerate(curves):
        centres, density, _ = log_binned_density(sizes, np.count_nonzero(np.asarray(sizes) > 0))
        # one marker per run (runs of one characteristic size can share a bin); hollow when not fitted
        line = ax.plot(centres, density, _MARKERS[k % len(_MARKERS)], ms=4.5 if fit is None else 3.5,
                       mfc="none" if fit is None else None, label=label + ("" if fit is not None else " (not fitted)"))[0]
        if fit is not None:
            p = np.geomspace(fit.xmin, float(np.max(sizes)), 50)
            scale = fit.n_tail / fit.n * (fit.alpha - 1) / fit.xmin
            ax.plot(p, scale * (p / fit.xmin) ** -fit.alpha, "-", lw=1.0, color=line.get_color(),
                    label=f"fit α = {fit.alpha:.3f}, P ≥ {fit.xmin:.3g}")
    ax.set(xscale="log", yscale="log", xlabel="potency P = Σ_j Δδ_j of the event",
           ylabel="probability density p(P)", title="event sizes (transient dropped)")
    ax.grid(alpha=0.25, lw=0.5, which="both")
    ax.legend(fontsize=7, frameon=False)
    return fig


def figure_space_time(panels, n_cols: int = 2):
    """Hypocentre against start time, one panel per run: marker area ∝ n_blocks, colour log10 P.

    ``panels``: (label, t_start, hypocentre, n_blocks, potency, t_cut, N) per run; ``t_cut`` (the start
    of the first kept event) is drawn as a dashed line; the vertical axis spans the N blocks.
    """
    from ...report import figures as F

    rows = -(-len(panels) // n_cols)
    cols = min(n_cols, len(panels))
    fig, axes = F._figure(3.3 * cols + 0.8, 2.6 * rows, ncols=cols, nrows=rows)
    logs = np.concatenate([np.log10(p[p > 0]) for *_, p, _, _ in panels]) if panels else np.zeros(1)
    lo, hi = float(np.min(logs)), float(np.max(logs))
    image = None
    for k, (label, t, hyp, nb, pot, cut, n) in enumerate(panels):
        ax = axes[k // cols][k % cols]
        image = ax.scatter(t, hyp, s=4 + 30 * nb / max(1, int(np.max(nb))), c=np.log10(np.maximum(pot, 1e-300)),
                           cmap="viridis", vmin=lo, vmax=hi if hi > lo else lo + 1, lw=0)
        if math.isfinite(cut):
            ax.axvline(cut, color="k", ls="--", lw=0.7)
        ax.set(xlabel="event start time t_start", ylabel="hypocentre (block, 0-based)", title=label,
               ylim=(-0.5, n - 0.5))
        ax.title.set_fontsize(8)
    for k in range(len(panels), rows * cols):
        axes[k // cols][k % cols].set_axis_off()
    if image is not None:
        fig.colorbar(image, ax=axes, label="log10 potency", shrink=0.9)
    return fig


#: Drawn for a run whose largest residual is exactly 0 (a log axis has no 0).
_FLOOR = 1e-18


def figure_balance(labels, events, balance, flag: float):
    """The largest stress-balance residual of each run's events against its events done; ``flag`` dashed."""
    from ...report import figures as F

    fig, axes = F._figure(5.0, 3.2)
    ax = axes[0][0]
    b = np.maximum(np.asarray(balance, dtype=float), _FLOOR)
    ax.plot(events, b, "o", ms=4, color="#444")
    ax.axhline(flag, color="#d95f02", ls="--", lw=1.0, label=f"flag: {flag:.0e}")
    ax.set(xscale="log", yscale="log", xlabel="events of the run", ylabel="max over events of |residual| / |Δstress|",
           title=f"stress balance per run ({len(labels)} runs)")
    ax.set_ylim(min(float(np.min(b)) / 10, 1e-16), max(float(np.max(b)) * 10, flag * 100))
    ax.grid(alpha=0.25, lw=0.5, which="both")
    ax.legend(fontsize=7, frameon=False)
    return fig
