"""The chain report's magnitude–frequency study near the uniform mode's ν_f = 1/2 (``[near_half]`` of the
workflow): budgeted catalogs per (ν, ν_f, N), their cutoff and spanning statistics, finite-size fits,
the reading (``scaling.mfd_reading``), the section text and its figure. Also the small-ν sweep
(``[sweep_small_nu]``) compared with the main sweep.
"""

from __future__ import annotations

import math
import time

import numpy as np

from .analysis import finite_size_fit, magnitude_frequency
from .scaling import mfd_reading, moment_cutoff, tapered_gr

__all__ = ["near_half_jobs", "near_half_section", "near_half_stats", "near_half_figure", "small_nu_jobs",
           "small_nu_section"]


def _budgeted_catalog(args) -> dict:
    """One catalog from the seeded random start: events after ``transient_cycles`` loading cycles are
    kept until ``events`` are kept, the driver has covered ``cycles`` loading cycles after the
    transient, ``cpu`` CPU seconds are spent, or one event lasts longer than ``longest_event`` cycles
    (t_max of the event; the unfinished event is not catalogued). ``cut`` says which bound stopped it."""
    from ...laws import resolve_law
    from ._loop import ChainLoop
    from ._validate import check_initial

    c, nh, nu, nu_f, n, cycles = args
    t0, c0 = time.perf_counter(), time.process_time()
    u0 = check_initial(n, c["ell"], c["ends"], None, c["amplitude"], nh["seed"])
    loop = ChainLoop(resolve_law(c["law"]), n, c["ell"], nu, nu_f, c["ends"], u0, t_max=nh["longest_event"] / nu)
    keys = ("t_start", "potency", "n_blocks", "hypocentre", "duration")
    cat = {k: [] for k in keys}
    t_first, cut, message = None, "events", ""
    while len(cat["potency"]) < nh["events"]:
        if time.process_time() - c0 > nh["cpu"]:
            cut = "cpu"
            break
        r = loop.run(1)
        if str(r["status"]) != "complete":
            cut, message = ("long event" if str(r["status"]) == "no-stop" else str(r["status"])), r["message"]
            break
        e = r["catalog"]
        t_first = float(e["t_start"][0]) if t_first is None else t_first
        if nu * (float(e["t_start"][0]) - t_first) < nh["transient_cycles"]:
            continue
        for k in keys:
            cat[k].append(float(e[k][0]) if k in ("t_start", "potency", "duration") else int(e[k][0]))
        if nu * (float(loop.t) - cat["t_start"][0]) >= cycles:
            cut = "cycles"
            break
    covered = nu * (float(loop.t) - cat["t_start"][0]) if cat["t_start"] else 0.0
    return {"nu": nu, "nu_f": nu_f, "n": n, "cycles_asked": cycles, "cycles": covered, "cut": cut,
            "message": message, "seconds": time.perf_counter() - t0, "cpu": time.process_time() - c0, **cat}


def near_half_jobs(cfg) -> list:
    """(function, args, cost guess) per catalog of ``[near_half]``."""
    c, nh = cfg["chain"], cfg.get("near_half")
    if not nh:
        return []
    jobs = []
    for nu, grid, sizes, cycles in zip(nh["nus"], nh["nu_f"], nh["sizes"], nh["cycles"]):
        for nf in grid:
            jobs += [(_budgeted_catalog, (c, nh, float(nu), float(nf), int(n), float(cy)), min(nh["cpu"], n * cy))
                     for n, cy in zip(sizes, cycles)]
    return jobs


def _row(r, c) -> dict:
    """Statistics of one budgeted catalog (docs/chain.md, "Cutoff and finite-size scaling")."""
    from .report import _catalog_stats

    n, p, nb = r["n"], np.array(r["potency"]), np.array(r["n_blocks"], dtype=int)
    out = {k: r[k] for k in ("nu", "nu_f", "n", "cycles_asked", "cycles", "cut", "message", "cpu")}
    out["events"] = int(p.size)
    if p.size < 20:
        return {**out, "fit": None}
    base = _catalog_stats({"n": n, "nu_f": r["nu_f"], "potency": r["potency"], "n_blocks": r["n_blocks"],
                           "t_start": r["t_start"], "seconds": r["seconds"], "status": r["cut"], "one_block": None})
    multi = nb >= 2
    p_min = 10 ** base["fit"]["m_min"]
    span = nb == n
    k = int(span.sum())
    big = int(np.argmax(p))
    out.update(fit=base["fit"], spanning=base["spanning"], mfd=base["mfd"],
               tapered=tapered_gr(p[multi], p_min), moments=moment_cutoff(p), moments_multi=moment_cutoff(p[multi]),
               largest={"potency": float(p[big]), "n_blocks": int(nb[big]),
                        "duration_cycles": r["nu"] * float(np.max(r["duration"]))},
               span_count=k, span_fraction=k / p.size, span_fraction_sigma=math.sqrt(max(k, 1)) / p.size,
               span_per_cycle=k / r["cycles"] if r["cycles"] > 0 else math.nan,
               one_block_fraction=float(np.mean(nb == 1)))
    return out


def near_half_stats(results, cfg) -> dict:
    """Rows per catalog and, per (ν, ν_f), finite-size fits over N of the cutoff ⟨P²⟩/⟨P⟩, the mean
    potency and the spanning fraction, and the reading (scaling.mfd_reading)."""
    rows = sorted((_row(r, cfg["chain"]) for r in results), key=lambda d: (-d["nu"], d["nu_f"], d["n"]))
    groups = []
    for nu, nf in sorted({(r["nu"], r["nu_f"]) for r in rows}, key=lambda x: (-x[0], x[1])):
        rs = [r for r in rows if r["nu"] == nu and r["nu_f"] == nf and r.get("fit")]
        fss = {}
        for key, val, sig in (("cutoff", lambda r: r["moments"]["cutoff"], lambda r: r["moments"]["cutoff_sigma"]),
                              ("mean", lambda r: r["moments"]["mean"], lambda r: r["moments"]["mean_sigma"]),
                              ("span", lambda r: r["span_fraction"], lambda r: r["span_fraction_sigma"])):
            use = [r for r in rs if key != "span" or r["span_count"] > 0]
            fss[key] = finite_size_fit([r["n"] for r in use], [val(r) for r in use], [sig(r) for r in use])
        reading = mfd_reading([{"n": r["n"], "tapered": r["tapered"], "spanning_excess": r["spanning"]["excess"]}
                               for r in rs], fss["cutoff"], fss["span"])
        groups.append({"nu": nu, "nu_f": nf, "sizes": [r["n"] for r in rs], "fss": fss, "reading": list(reading)})
    return {"rows": rows, "groups": groups}


def _pm(x, s, d=2) -> str:
    if x is None or not math.isfinite(x):
        return "–"
    return f"{x:.{d}f} ± {s:.{d}f}" if math.isfinite(s) else f"{x:.{d}f}"


def _g(x, s) -> str:
    if not math.isfinite(x):
        return "∞" if x == math.inf else "–"
    return f"{x:.3g} ± {s:.2g}" if math.isfinite(s) else f"{x:.3g}"


def _law(f) -> str:
    if not math.isfinite(f.get("theta", math.nan)):
        return f"no fit ({f['points']} sizes)"
    return (f"∝ N^{-f['theta']:.2f}±{f['theta_sigma']:.2f} (χ²/dof {f['chi2_power'] / max(f['dof_power'], 1):.1f}; "
            f"N = {', '.join(str(int(n)) for n in f['sizes'])})")


def near_half_section(cfg, nh) -> list:
    """The report section (markdown lines)."""
    c = cfg["near_half"]
    L = ["## Magnitude–frequency near ν_f = 1/2 and its finite-size scaling", "",
         "Large groups of blocks keep the single block's threshold ν_f = 1/2 (their softest mode feels the "
         "pulling springs only, docs/chain.md \"Threshold\"), so this is where Mori & Kawamura place near-critical "
         "behaviour. One catalog per (ν, ν_f, N) from the seeded random start (seed "
         f"{c['seed']}), after a transient of {c['transient_cycles']} loading cycles, bounded by each of: "
         f"{c['events']} events, a number of loading cycles per N (below), {c['cpu']} CPU seconds, and one event "
         f"lasting longer than {c['longest_event']} loading cycles (that event is not catalogued: the chain "
         "slides). The column *cut* says which bound ended the catalog; *cpu* cuts depend on the machine. "
         "b: Page's estimator as in the catalog table above (multi-block events, from the most populated bin "
         "to below the smallest spanning event). Tapered law: maximum-likelihood b and corner potency of "
         "N(≥P) ∝ P^-b e^-P/P_corner over the multi-block events above the same m_min, spanning events included "
         "(scaling.tapered_gr; KS against 1.36/√n). Cutoff: P_c = ⟨P²⟩/⟨P⟩ over all events, σ by 10 batch "
         "means (scaling.moment_cutoff; docs/chain.md \"Cutoff and finite-size scaling\"). Spanning: "
         "n_blocks = N, σ = √k/events.", "", "![mfd near 1/2](fig_mfd_half.png)", "",
         "| ν | ν_f | N | cycles (asked) | events | cut | b (Page) [m range] | tapered b | P_corner | tapered KS / crit | "
         "largest P (n_blocks, cycles) | ⟨P⟩ | P_c = ⟨P²⟩/⟨P⟩ | spanning: count, fraction (per cycle) | "
         "excess over GR | CPU s |", "|" + "---|" * 16]
    for r in nh["rows"]:
        head = f"| {r['nu']:g} | {r['nu_f']:g} | {r['n']} | {r['cycles']:.1f} ({r['cycles_asked']:g}) | {r['events']} | {r['cut']} |"
        if not r.get("fit"):
            L.append(head + " fewer than 20 events" + " |" * 9 + f" {r['cpu']:.0f} |")
            continue
        f, t, m, lg = r["fit"], r["tapered"], r["moments"], r["largest"]
        L.append(head + f" {_pm(f['b'], f['sigma'])} [{f['m_min']:.1f}, {f['m_max']:.1f}] | {_pm(t['b'], t['b_sigma'])} | "
                 f"{_g(t['corner'], t['corner_sigma'])} | {t['ks']:.3f} / {t['ks_crit']:.3f} | "
                 f"{lg['potency']:.3g} ({lg['n_blocks']}, {lg['duration_cycles']:.2f}) | {_g(m['mean'], m['mean_sigma'])} | "
                 f"{_g(m['cutoff'], m['cutoff_sigma'])} | {r['span_count']}, {r['span_fraction']:.2g} "
                 f"({r['span_per_cycle']:.2g}) | {r['spanning']['excess']:.3g} | {r['cpu']:.0f} |")
    L += ["", "Finite-size fits over N (analysis.finite_size_fit, power law y = A N^a with a = −θ, weighted on "
          "ln y; spanning fraction over the sizes with at least one spanning event) and the reading "
          "(scaling.mfd_reading: *critical-like* = the cutoff grows with N and one tapered power law with the "
          "same b > 0 fits every N without a spanning excess; *characteristic-size* = an exponential law (b ≈ 0) "
          "at the largest N, or spanning events in excess of the power law with a spanning fraction that "
          "does not decrease with N):", "",
          "| ν | ν_f | cutoff P_c | mean ⟨P⟩ | spanning fraction | reading |", "|---|---|---|---|---|---|"]
    for g in nh["groups"]:
        f = g["fss"]
        L.append(f"| {g['nu']:g} | {g['nu_f']:g} | {_law(f['cutoff'])} | {_law(f['mean'])} | {_law(f['span'])} | "
                 f"**{g['reading'][0]}**: {g['reading'][1]} |")
    L.append("")
    return L


def near_half_figure(out, nh) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    groups = nh["groups"]
    fig, axes = plt.subplots(1, len(groups) + 1, figsize=(3.6 * (len(groups) + 1), 3.8), squeeze=False)
    for ax, g in zip(axes[0], groups):
        for r in nh["rows"]:
            if r["nu"] != g["nu"] or r["nu_f"] != g["nu_f"] or not r.get("fit"):
                continue
            e, cnt = np.array(r["mfd"]["edges"]), np.array(r["mfd"]["counts"], dtype=float)
            mid = (e[1:] + e[:-1]) / 2
            cum = cnt[::-1].cumsum()[::-1] / max(r["cycles"], 1e-300)     # N(≥ m) per loading cycle
            ax.semilogy(mid[cum > 0], cum[cum > 0], "-", label=f"N = {r['n']}")
        ax.set(title=f"ν = {g['nu']:g}, ν_f = {g['nu_f']:g}", xlabel="m = log10 P")
        ax.legend(fontsize=6)
    axes[0][0].set_ylabel("events with potency ≥ P, per loading cycle")
    ax = axes[0][-1]
    for g in groups:
        rs = [r for r in nh["rows"] if r["nu"] == g["nu"] and r["nu_f"] == g["nu_f"] and r.get("fit")]
        if rs:
            ax.errorbar([r["n"] for r in rs], [r["moments"]["cutoff"] for r in rs],
                        yerr=[r["moments"]["cutoff_sigma"] for r in rs], fmt="o-" if g["nu"] >= 1e-3 else "s--",
                        ms=3, capsize=2, label=f"ν = {g['nu']:g}, ν_f = {g['nu_f']:g}")
    ax.set(xscale="log", yscale="log", xlabel="N", ylabel="P_c = ⟨P²⟩/⟨P⟩", title="cutoff potency against N")
    ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(out / "fig_mfd_half.png", dpi=110)
    plt.close(fig)


def _sweep_small_nu(args) -> dict:
    """A sweep of ``[sweep_small_nu]``: the main sweep's runner (``report._sweep``) at another ν."""
    from .report import _sweep

    return _sweep(args)


def small_nu_jobs(cfg) -> list:
    """The ``[sweep_small_nu]`` sweeps: the main sweep's runner at another ν."""
    s = cfg.get("sweep_small_nu")
    if not s:
        return []
    c = dict(cfg["chain"], nu=s["nu"])
    sw = dict(cfg["sweep"], **{k: s[k] for k in ("transient_cycles", "max_events_per_step") if k in s})
    jobs = []
    for n, seeds, cycles in zip(s["sizes"], s["seeds"], s["cycles_per_step"]):
        grid = [float(x) for x in s.get("nu_f", cfg["sweep"]["nu_f"])]
        jobs += [(_sweep_small_nu, (c, sw, n, seed, grid, cycles), n * cycles * 10) for seed in range(1, seeds + 1)]
    return jobs


def small_nu_section(cfg, small, main) -> list:
    """D (up branch) per ν_f at the small ν beside the main ν for the same N, and jump / loop width."""
    nu0, nu1 = cfg["chain"]["nu"], cfg["sweep_small_nu"]["nu"]
    grid = small["table"][0]["nu_f"]
    L = [f"### The sweep at ν = {nu1:g} against ν = {nu0:g}", "",
         f"The same ν_f sweep (up, then down) at ν = {nu1:g} for the small chains "
         f"(`[sweep_small_nu]`: N = {', '.join(str(r['n']) for r in small['table'])}, seeds "
         f"{', '.join(str(r['seeds']) for r in small['table'])}, steps of "
         f"{', '.join(f'{x:g}' for x in cfg['sweep_small_nu']['cycles_per_step'])} loading cycles). D on the up branch "
         "(mean ± standard error over seeds); the single block's D → 0 for ν_f > 1/2 and a lone block's slip → 0 "
         "above ν_f* as ν → 0, so the curves sharpen where they are first-order-like:", "",
         "| N | ν | " + " | ".join(f"{x:g}" for x in grid) + " | D jump (at) | D loop width (at) | events | CPU s |",
         "|---|---|" + "---|" * len(grid) + "---|---|---|---|"]
    by_n = {r["n"]: r for r in main["table"]}
    for r in small["table"]:
        for nu, row in ((nu0, by_n.get(r["n"])), (nu1, r)):
            if row is None:
                continue
            d = row["slip_per_block"]
            cells = [_pm(d["up"][row["nu_f"].index(x)], d["se_up"][row["nu_f"].index(x)], 3)
                     if x in row["nu_f"] and math.isfinite(d["up"][row["nu_f"].index(x)]) else "" for x in grid]
            L.append(f"| {r['n']} | {nu:g} | " + " | ".join(cells) +
                     f" | {_pm(d['jump_sign'] * d['jump'], d['jump_sigma'], 3)} ({d['jump_at'][0]:g}→{d['jump_at'][1]:g}) | "
                     f"{_pm(d['width'], d['width_sigma'], 3)} ({d['width_at']:g}) | {row['events']} | {row['seconds']:.0f} |")
    L.append("")
    return L
