"""The report's figures, drawn with matplotlib's object API on the Agg canvas (no pyplot state).

Each ``figure_*`` function returns a ``matplotlib.figure.Figure``; ``save`` writes it as a
deterministic PNG (fixed size and dpi, no software/date metadata), so the same data give the same bytes.
Units: Δ in F0/k, ν and ν_f in V0 = F0/√(mk), times in √(m/k) (Eqs. 4–5 of the paper).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ..analysis.extrapolate import PAPER_CL_HALF

__all__ = ["DPI", "figure_critical", "figure_fig2", "figure_fig3", "figure_period", "figure_rounding",
           "save"]

DPI = 110
_LAW_TITLE = {"piecewise-linear": "piecewise-linear law, Eq. (12)",
              "carlson-langer": "Carlson–Langer law, Eq. (19)"}
_NU_F_COLORS = {0.2: "#1b9e77", 0.3: "#d95f02", 0.4: "#7570b3"}


def _ordered(paper_order, present) -> list:
    """The paper's laws in ``paper_order`` first (its figures unchanged), then any other law present."""
    return [law for law in paper_order if law in present] + sorted(law for law in present if law not in paper_order)


def _title(law: str) -> str:
    return _LAW_TITLE.get(law, f"law {law}")


def _figure(width: float, height: float, ncols: int = 1, nrows: int = 1, **kw):
    fig = Figure(figsize=(width, height), dpi=DPI, layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(nrows, ncols, squeeze=False, **kw)
    return fig, axes


def save(fig: Figure, path) -> Path:
    """Write ``fig`` as a PNG that depends only on its content (no date, no software tag)."""
    path = Path(path)
    fig.savefig(path, dpi=DPI, format="png", metadata={"Software": None})
    return path


def _nu_label(nu: float) -> str:
    e = math.log10(nu)
    return f"ν = 1e{round(e)}" if abs(e - round(e)) < 1e-9 else f"ν = {nu:.1e}"


def _nu_colors(nus):
    import matplotlib

    cmap = matplotlib.colormaps["viridis"]
    nus = sorted(nus, reverse=True)
    n = max(len(nus) - 1, 1)
    return {nu: cmap(0.85 * i / n) for i, nu in enumerate(nus)}


def _delta_vs_nu_f(ax, curves, colors):
    for nu, (x, d) in sorted(curves.items(), reverse=True):
        ax.plot(x, d, "-", lw=1.2, color=colors[nu], label=_nu_label(nu))


def _limit_line(ax, x, d, label=None, *, lo=-math.inf, hi=1.0, lw=1.6, jump=True, **kw) -> float:
    """The ν → 0 curve over [lo, hi]: Δ0 up to 1/2, 0 above, the jump a dotted vertical (if ``jump``).

    Returns the largest Δ0 drawn.
    """
    x, d = np.asarray(x), np.asarray(d)
    shown = (x >= lo) & (x <= 0.5)
    ax.plot(x[shown], d[shown], color="k", lw=lw, label=label, **kw)
    ax.plot([0.5, hi], [0, 0], color="k", lw=lw, **kw)
    if jump:
        ax.plot([0.5, 0.5], [0, d[shown][-1]], color="k", lw=0.8, ls=":")
    return float(np.max(d[shown]))


def _delta_axes(ax, title: str, legend_loc: str) -> None:
    """Labels, title, the ν_f = 1/2 line, legend and grid of a Δ-vs-ν_f panel."""
    ax.set_xlabel("friction velocity ν_f  [V0]")
    ax.set_ylabel("slip per cycle Δ  [F0/k]")
    ax.set_title(title)
    ax.axvline(0.5, color="0.7", lw=0.6, zorder=0)
    ax.legend(loc=legend_loc, frameon=False)
    ax.grid(alpha=0.25, lw=0.5)


def figure_fig2(curves: dict, limit_nu_f, limit_delta, eq18_nu_f, eq18_delta) -> Figure:
    """The paper's Fig. 2: Δ vs ν_f for the piecewise-linear law at several ν, Eq. (18), direct limit."""
    fig, axes = _figure(6.0, 4.0)
    ax = axes[0, 0]
    colors = _nu_colors(curves)
    _delta_vs_nu_f(ax, curves, colors)
    _limit_line(ax, eq18_nu_f, eq18_delta, "Eq. (18), ν → 0", ls="--")
    ax.plot(limit_nu_f, limit_delta, "o", ms=4.5, mfc="none", mec="crimson", mew=1.1,
            label="direct ν → 0 limit (engine)")
    ax.set_xlim(0, 1)
    ax.set_ylim(-0.05, 2.1)
    _delta_axes(ax, "Fig. 2: " + _LAW_TITLE["piecewise-linear"], "lower left")
    return fig


def figure_fig3(curves: dict, limit_nu_f, limit_delta, extrapolation=None, paper=PAPER_CL_HALF) -> Figure:
    """The paper's Fig. 3: Carlson–Langer at ν = 1e-9 (and other ν), the direct limit, the 0.17."""
    fig, axes = _figure(6.0, 4.0)
    ax = axes[0, 0]
    colors = _nu_colors(curves)
    for nu, (x, d) in sorted(curves.items(), reverse=True):
        main = abs(math.log10(nu) + 9) < 1e-6
        ax.plot(x, d, "-", lw=2.0 if main else 0.9, color=colors[nu], alpha=1 if main else 0.7,
                label=_nu_label(nu) + (" (the paper's ν)" if main else ""))
    _limit_line(ax, limit_nu_f, limit_delta, "direct ν → 0 limit (engine)")
    ax.plot([0.5], [paper], "X", ms=8, color="crimson", label=f"paper: Δ = {paper} at ν_f = 1/2 (extrapolated)")
    if extrapolation is not None:
        ax.errorbar([0.5], [extrapolation.delta0_extrapolated], yerr=[extrapolation.uncertainty], fmt="s",
                    ms=4, color="tab:blue", capsize=3,
                    label=f"our extrapolation {extrapolation.delta0_extrapolated:.4f} ± "
                          f"{extrapolation.uncertainty:.0e}")
    ax.set_xlim(0, 1)
    top = max([float(np.nanmax(d)) for _, d in curves.values()] + [float(np.nanmax(limit_delta))])
    ax.set_ylim(-0.03 * top, 1.05 * top)
    _delta_axes(ax, "Fig. 3: " + _LAW_TITLE["carlson-langer"], "upper right")
    inset = ax.inset_axes([0.62, 0.12, 0.35, 0.34])
    for nu, (x, d) in sorted(curves.items(), reverse=True):
        m = (x >= 0.46) & (x <= 0.54)
        inset.plot(x[m], d[m], "-", lw=1.0, color=colors[nu])
    _limit_line(inset, limit_nu_f, limit_delta, lo=0.46, hi=0.54, lw=1.4, jump=False)
    inset.plot([0.5], [paper], "X", ms=6, color="crimson")
    inset.set_xlim(0.46, 0.54)
    inset.set_ylim(-0.02, 0.5)
    inset.tick_params(labelsize=6.5)
    inset.set_title("near ν_f = 1/2", fontsize=7)
    return fig


def figure_critical(extrapolations: dict) -> Figure:
    """Δ at ν_f = 1/2 against ε = 1/W(1/(2eν)), with the fit, the direct limit and the paper's values."""
    from ..analysis.extrapolate import critical_epsilon

    laws = _ordered(("carlson-langer", "piecewise-linear"), extrapolations)
    fig, axes = _figure(4.2 * max(len(laws), 1), 4.0, ncols=max(len(laws), 1))
    for ax, law in zip(axes[0], laws):
        ex = extrapolations[law]
        eps = critical_epsilon(ex.nu)
        ax.plot(eps, ex.delta, "o", ms=3.5, color="tab:blue", label="engine, finite ν")
        if ex.curve:
            x, y = ex.curve
            window = ex.nu[eps <= x.max() * (1 + 1e-12)].max()
            ax.plot(x, y, "-", lw=1.0, color="tab:blue", alpha=0.7, label=f"fit: polynomial in ε (ν ≤ {window:.0e})")
        ax.errorbar([0.004], [ex.delta0_extrapolated], yerr=[ex.uncertainty], fmt="s", ms=4,
                    color="tab:blue", capsize=3,
                    label=f"extrapolated {ex.delta0_extrapolated:.5f} ± {ex.uncertainty:.0e}")
        ax.plot([0], [ex.delta0_direct], "*", ms=11, color="k", zorder=5,
                label=f"direct ν → 0 limit {ex.delta0_direct:.6f}")
        if ex.paper_value is not None:
            name = "paper, Eq. (18): √e" if law == "piecewise-linear" else f"paper: {ex.paper_value}"
            ax.plot([0], [ex.paper_value], "X", ms=8, color="crimson", zorder=4, label=name)
        ax.set_xlim(-0.006, float(eps.max()) * 1.05)
        ax.set_xlabel("ε = 1/W(1/(2eν))  (≈ 1/ln(1/ν))")
        ax.set_ylabel("slip per cycle Δ at ν_f = 1/2  [F0/k]")
        ax.set_title(_title(law))
        ax.grid(alpha=0.25, lw=0.5)
        ax.legend(loc="upper left", frameon=False)
        top = ax.twiny()
        top.set_xlim(ax.get_xlim())
        ticks = np.array([1e-3, 1e-5, 1e-7, 1e-9, 1e-15])
        top.set_xticks(critical_epsilon(ticks))
        top.set_xticklabels([f"1e{round(math.log10(t))}" for t in ticks], fontsize=6.5)
        top.set_xlabel("pulling speed ν  [V0]", fontsize=8)
    return fig


def figure_period(fits) -> Figure:
    """T − Δ0/ν against ν with the fitted expansion and the naive (α − ω) ln(1/ν), and the residuals."""
    laws = _ordered(("piecewise-linear", "carlson-langer"), {f.law for f in fits})
    fig, axes = _figure(5.0 * max(len(laws), 1), 6.4, ncols=max(len(laws), 1), nrows=2,
                        gridspec_kw={"height_ratios": [2.2, 1]}, sharex="col")
    for col, law in enumerate(laws):
        ax, res = axes[0, col], axes[1, col]
        for n, f in enumerate(sorted((f for f in fits if f.law == law), key=lambda f: f.nu_f)):
            c = _NU_F_COLORS.get(round(f.nu_f, 6), f"C{n}")   # one colour per ν_f for its four artists
            pos = f.excess > 0
            ax.loglog(f.nu[pos], f.excess[pos], "o", ms=3.2, color=c,
                      label=f"ν_f = {f.nu_f:g}: fitted ln coeff. {f.log_coefficient:.6f} (α − ω = "
                            f"{f.log_coefficient_expected:.6f}), K = {f.K:.3g}, r = {f.exponent_r:.4f}")
            grid = np.logspace(math.log10(f.nu.min()), math.log10(f.nu.max()), 200)
            model = f.predict(grid)
            ax.loglog(grid, np.where(model > 0, model, np.nan), "-", lw=1.0, color=c)
            ax.loglog(grid, f.log_coefficient_expected * np.log(1 / grid), "--", lw=0.9, color=c, alpha=0.8)
            res.semilogx(f.nu, f.residuals / f.errors, "o", ms=2.8, color=c)
        ax.plot([], [], "o", ms=3.2, color="0.4", label="engine: T − Δ0/ν (Δ0 the direct limit)")
        ax.plot([], [], "-", color="0.4", label="fit: (α−ω) ln(1/ν) + C0 + K ν^−r + higher terms")
        ax.plot([], [], "--", color="0.4", label="the paper's correction (α − ω) ln(1/ν) alone")
        ax.set_ylabel("T − Δ0/ν  [√(m/k)]")
        ax.set_title(_title(law))
        ax.grid(alpha=0.25, lw=0.5, which="both")
        # Headroom for the legend: the data keep the lower 60 % of the (log) height, the legend's six
        # lines the top, so no legend text lies over the steepest (ν_f = 0.4) series.
        low, high = ax.get_ylim()
        ax.set_ylim(low, low * (high / low) ** (1 / 0.6))
        ax.legend(loc="upper left", frameon=False, fontsize=6.5)
        res.axhspan(-1, 1, color="0.85", zorder=0)
        res.axhline(0, color="0.5", lw=0.6)
        res.set_ylim(-4, 4)
        res.set_xlabel("pulling speed ν  [V0]")
        res.set_ylabel("residual / data error")
        res.grid(alpha=0.25, lw=0.5)
        res.invert_xaxis()
    return fig


def figure_rounding(curves_by_law: dict, limits_by_law: dict, band=(0.44, 0.56)) -> Figure:
    """Finite-ν rounding of the transition: Δ vs ν_f near 1/2 at several ν, and the ν → 0 jump."""
    laws = [law for law in ("piecewise-linear", "carlson-langer") if law in curves_by_law]
    fig, axes = _figure(4.6 * max(len(laws), 1), 3.9, ncols=max(len(laws), 1))
    for ax, law in zip(axes[0], laws):
        curves = curves_by_law[law]
        colors = _nu_colors(curves)
        for nu, (x, d) in sorted(curves.items(), reverse=True):
            ax.plot(x, d, "-", lw=1.1, color=colors[nu], label=_nu_label(nu))
        top = max([float(np.nanmax(d)) for _, d in curves.values()] + [0.1])
        if law in limits_by_law:
            lx, ld = limits_by_law[law]
            drawn = _limit_line(ax, lx, ld, "ν → 0 (direct limit)", lo=band[0] - 0.01, hi=band[1], lw=1.8)
            top = max(top, drawn)
        ax.set_xlim(*band)
        ax.set_ylim(-0.03 * top, 1.05 * top)
        _delta_axes(ax, _LAW_TITLE[law], "lower left")
    return fig
