"""Figures of the chain report (``study.main``): order parameter loops, finite-size scaling,
magnitude–frequency, lone-block threshold."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

__all__ = ["figures"]

#: No "Software" tag (the matplotlib version): the same data give the same bytes across versions of it.
_NO_SOFTWARE = {"Software": None}


def figures(out: Path, data: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sw = data["sweeps"]
    ell = _ell(data)
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for row in sw["table"]:
        x = np.array(row["nu_f"])
        for a, key in zip(ax, ("slip_per_block", "psi")):
            d = row[key]
            line = a.errorbar(x, d["up"], yerr=d["se_up"], fmt="o-", ms=3, capsize=2,
                              label=f"N = {row['n']} ({row['seeds']} seed{'s' * (row['seeds'] > 1)})")
            a.errorbar(x, d["down"], yerr=d["se_down"], fmt="s--", ms=3, capsize=2, color=line[0].get_color())
    for a in ax:
        a.axvline(0.5 / math.sqrt(1 + 2 * ell**2), color="gray", lw=0.8)
        a.axvline(0.5, color="gray", lw=0.8, ls=":")
        a.set_xlabel("ν_f")
    ax[0].set(yscale="log", ylabel="D = ΣP / Σ n_blocks (slip per block per event)",
              title="up (solid) then down (dashed) within one run")
    ax[1].set(ylabel="Ψ = spanning slip / (N ν ΔT)")
    ax[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "fig_order.png", dpi=110, metadata=_NO_SOFTWARE)
    plt.close(fig)

    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    chains = [r for r in sw["table"] if r["n"] > 1]
    ns = np.array([r["n"] for r in chains], dtype=float)
    for a, key, title in zip(ax, ("slip_per_block", "psi"), ("D", "Ψ")):
        for q, mk in (("jump", "o"), ("width", "s")):
            y = np.array([r[key][q] for r in chains])
            s = np.array([r[key][q + "_sigma"] for r in chains])
            line = a.errorbar(ns, y, yerr=s, fmt=mk, capsize=3, label=f"{q} of {title}")
            f = sw["fss"][f"{key}.{q}"]
            if math.isfinite(f["theta"]):
                nn = np.geomspace(ns.min(), ns.max(), 50)
                a.plot(nn, f["amplitude"] * nn ** -f["theta"], "-", color=line[0].get_color(), lw=0.8,
                       label=f"A N^-θ, θ = {f['theta']:.2f} ± {f['theta_sigma']:.2f}")
                a.axhline(f["constant"], color=line[0].get_color(), lw=0.6, ls=":",
                          label=f"constant {f['constant']:.3g}")
        a.set(xscale="log", yscale="log", xlabel="N", title=f"finite-size scaling of {title}",
              ylabel=f"{title}: |jump|, loop width (± s.e. over seeds)")
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "fig_fss.png", dpi=110, metadata=_NO_SOFTWARE)
    plt.close(fig)

    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    for s in data["catalogs"]:
        e, c = np.array(s["mfd"]["edges"]), np.array(s["mfd"]["counts"])
        mid = (e[1:] + e[:-1]) / 2
        lab = f"N = {s['n']}, ν_f = {s['nu_f']}"
        f = s["fit"]
        # no b where no decreasing exponential fits the magnitudes (analysis.b_value gives NaN): say so
        b = f"b = {f['b']:.2f}" if math.isfinite(f["b"]) else "no b-value (not decreasing)"
        line, = ax[0].semilogy(mid[c > 0], c[c > 0], "o-", ms=3, lw=0.8, label=f"{lab}, {b}")
        if math.isfinite(f["b"]):
            mm = np.linspace(f["m_min"], f["m_max"], 20)
            n0 = f["n"] * (1 - 10 ** (-f["b"] * 0.1)) / (1 - 10 ** (-f["b"] * (f["m_max"] - f["m_min"])))
            ax[0].plot(mm, n0 * 10 ** (-f["b"] * (mm - f["m_min"])), "--", color=line.get_color(), lw=1.6)
        pot = np.array(s["mfd"]["potency"])
        ax[1].semilogy(mid[pot > 0], pot[pot > 0], "o-", ms=3, label=lab)
    ax[0].set(xlabel="m = log10 P", ylabel="events per 0.1 in m", title="magnitude–frequency (dashed: the truncated-exponential fit)")
    ax[1].set(xlabel="m = log10 P", ylabel="potency per 0.1 in m")
    ax[0].legend(fontsize=7), ax[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "fig_mfd.png", dpi=110, metadata=_NO_SOFTWARE)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(6, 4))
    for t in data["threshold"]:
        ax.semilogy(t["scan_ratio"], t["scan_delta"], "o-", ms=2,
                    label=f"ℓ = {t['ell']}, {'free end' if t['end'] else 'interior'} (k = {t['rows'][0]['k']:g})")
    ax.axvline(1.0, color="gray", lw=0.8)
    ax.set(xlabel="ν_f / ν_f*,   ν_f* = 1/(2√k)", ylabel="k·P of the lone block",
           title=f"lone block among stuck neighbours, ν = {data['threshold'][0]['scan_nu']:g}")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "fig_threshold.png", dpi=110, metadata=_NO_SOFTWARE)
    plt.close(fig)


def _ell(data) -> float:
    import tomllib

    return float(tomllib.loads(data["workflow"])["chain"]["ell"])
