"""The chain report's magnitude–frequency study near the uniform mode's ν_f = 1/2 (``[near_half]`` of the
workflow): budgeted catalogs per (ν, ν_f, N), their cutoff and spanning statistics, finite-size fits,
the reading (``scaling.mfd_reading``), the section text and its figure. Also the small-ν sweep
(``[sweep_small_nu]``) compared with the main sweep.
"""

from __future__ import annotations

import math
import time

import numpy as np

from .analysis import finite_size_fit
from .scaling import MERGED, mfd_reading, moment_cutoff, tapered_gr

__all__ = ["near_half_figure", "near_half_jobs", "near_half_section", "near_half_stats", "small_nu_jobs",
           "small_nu_section", "verdict_notes"]


def _budgeted_catalog(args) -> dict:
    """One catalog from the seeded random start: events after ``transient`` loading cycles are
    kept until ``events`` are kept, the driver has covered ``cycles`` loading cycles after the
    transient, ``cpu`` CPU seconds are spent, or one event lasts longer than ``longest_event`` cycles
    (t_max of the event; the unfinished event is not catalogued). ``cut`` says which bound stopped it."""
    from ...laws import resolve_law
    from ._loop import ChainLoop
    from ._validate import check_initial

    c, nh, nu, nu_f, n, cycles, transient = args
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
        if nu * (float(e["t_start"][0]) - t_first) < transient:
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
    """(function, args, cost guess) per catalog of ``[near_half]``; the guess is in the units of
    ``report._jobs`` (N × cycles of a sweep, ~1/8 CPU second: measured 5 ms per block and loading cycle
    for a catalog at ν = 1e-3, ten times more at 1e-4)."""
    c, nh = cfg["chain"], cfg.get("near_half")
    if not nh:
        return []
    jobs = []
    tr = nh["transient_cycles"]
    tr = tr if isinstance(tr, list) else [tr] * len(nh["nus"])
    for nu, grid, sizes, cycles, t in zip(nh["nus"], nh["nu_f"], nh["sizes"], nh["cycles"], tr):
        for nf in grid:
            jobs += [(_budgeted_catalog, (c, nh, float(nu), float(nf), int(n), float(cy), float(t)),
                      8 * min(nh["cpu"], 0.005 * n * cy * 1e-3 / nu)) for n, cy in zip(sizes, cycles)]
    return jobs


def _row(r) -> dict:
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
    t, dur = np.array(r["t_start"]), np.array(r["duration"])
    elapsed = t[-1] + dur[-1] - t[0]
    big = int(np.argmax(p))
    out.update(fit=base["fit"], spanning=base["spanning"], mfd=base["mfd"],
               tapered=tapered_gr(p[multi], p_min), moments=moment_cutoff(p), moments_multi=moment_cutoff(p[multi]),
               largest={"potency": float(p[big]), "n_blocks": int(nb[big]),
                        "duration_cycles": r["nu"] * float(np.max(r["duration"]))},
               span_count=k, span_fraction=k / p.size, span_fraction_sigma=math.sqrt(max(k, 1)) / p.size,
               span_per_cycle=k / r["cycles"] if r["cycles"] > 0 else math.nan,
               one_block_fraction=float(np.mean(nb == 1)),
               # Σ duration / elapsed time: near 1 the chain is rarely all stuck, so one catalogued event
               # holds many separate slips (docs/chain.md, "Order parameter")
               slip_fraction=float(dur.sum() / elapsed),
               events_per_block_cycle=float(p.size / (r["nu"] * elapsed * n)))
    return out


def near_half_stats(results, cfg) -> dict:
    """Rows per catalog and, per (ν, ν_f), finite-size fits over N of the cutoff ⟨P²⟩/⟨P⟩, the mean
    potency and the spanning fraction, and the reading (scaling.mfd_reading)."""
    rows = sorted((_row(r) for r in results), key=lambda d: (-d["nu"], d["nu_f"], d["n"]))
    groups = []
    for nu, nf in sorted({(r["nu"], r["nu_f"]) for r in rows}, key=lambda x: (-x[0], x[1])):
        rs = [r for r in rows if r["nu"] == nu and r["nu_f"] == nf and r.get("fit")]
        fss = {}
        for key, val, sig in (("cutoff", lambda r: r["moments"]["cutoff"], lambda r: r["moments"]["cutoff_sigma"]),
                              ("mean", lambda r: r["moments"]["mean"], lambda r: r["moments"]["mean_sigma"]),
                              ("span", lambda r: r["span_fraction"], lambda r: r["span_fraction_sigma"])):
            use = [r for r in rs if key != "span" or r["span_count"] > 0]
            fss[key] = finite_size_fit([r["n"] for r in use], [val(r) for r in use], [sig(r) for r in use])
        reading = mfd_reading([{"n": r["n"], "tapered": r["tapered"], "spanning_excess": r["spanning"]["excess"],
                                "slip_fraction": r["slip_fraction"]} for r in rs], fss["cutoff"], fss["span"])
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
         f"{c['seed']}), after a transient of {c['transient_cycles']} loading cycles (per ν), bounded by each of: "
         f"{c['events']} events, a number of loading cycles per N (below), {c['cpu']} CPU seconds, and one event "
         f"lasting longer than {c['longest_event']} loading cycles (that event is not catalogued: the chain "
         "slides). The column *cut* says which bound ended the catalog; *cpu* cuts depend on the machine. "
         "b: Page's estimator as in the catalog table above (multi-block events, from the most populated bin "
         "to below the smallest spanning event). Tapered law: maximum-likelihood b and corner potency of "
         "N(≥P) ∝ P^-b e^-P/P_corner over the multi-block events above the same m_min, spanning events included "
         "(scaling.tapered_gr; KS against 1.36/√n). Cutoff: P_c = ⟨P²⟩/⟨P⟩ over all events, σ by 10 batch "
         "means (scaling.moment_cutoff; docs/chain.md \"Cutoff and finite-size scaling\"). Spanning: "
         "n_blocks = N, σ = √k/events. Slipping fraction: Σ duration / elapsed time; an event ends only when "
         "the whole chain is stuck, so where this is near 1 one catalogued event holds many separate slips "
         "(the events per block and loading cycle fall with N) and its potency adds them up.", "", "![mfd near 1/2](fig_mfd_half.png)", "",
         "| ν | ν_f | N | cycles (asked) | events | cut | b (Page) [m range] | tapered b | P_corner | tapered KS / crit | "
         "largest P (n_blocks, cycles) | ⟨P⟩ | P_c = ⟨P²⟩/⟨P⟩ | spanning: count, fraction (per cycle) | "
         "excess over GR | slipping fraction (events per block and cycle) | CPU s |", "|" + "---|" * 17]
    for r in nh["rows"]:
        head = f"| {r['nu']:g} | {r['nu_f']:g} | {r['n']} | {r['cycles']:.1f} ({r['cycles_asked']:g}) | {r['events']} | {r['cut']} |"
        if not r.get("fit"):
            L.append(head + " fewer than 20 events" + " |" * 10 + f" {r['cpu']:.0f} |")
            continue
        f, t, m, lg = r["fit"], r["tapered"], r["moments"], r["largest"]
        L.append(head + f" {_pm(f['b'], f['sigma'])} [{f['m_min']:.1f}, {f['m_max']:.1f}] | {_pm(t['b'], t['b_sigma'])} | "
                 f"{_g(t['corner'], t['corner_sigma'])} | {t['ks']:.3f} / {t['ks_crit']:.3f} | "
                 f"{lg['potency']:.3g} ({lg['n_blocks']}, {lg['duration_cycles']:.2f}) | {_g(m['mean'], m['mean_sigma'])} | "
                 f"{_g(m['cutoff'], m['cutoff_sigma'])} | {r['span_count']}, {r['span_fraction']:.2g} "
                 f"({r['span_per_cycle']:.2g}) | {r['spanning']['excess']:.3g} | {r['slip_fraction']:.2f} "
                 f"({r['events_per_block_cycle']:.3g}) | {r['cpu']:.0f} |")
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
    L += _summary(nh)
    L += _nu_comparison(nh)
    L.append("")
    return L


def _span(xs, fmt="{:.2g}") -> str:
    xs = [x for x in xs if math.isfinite(x)]
    if not xs:
        return "–"
    lo, hi = min(xs), max(xs)
    return fmt.format(lo) if fmt.format(lo) == fmt.format(hi) else fmt.format(lo) + "–" + fmt.format(hi)


def _summary(nh) -> list:
    """In words, with the numbers: what the distributions near 1/2 look like, per N."""
    rows = [r for r in nh["rows"] if r.get("fit")]
    if not rows:
        return []
    sizes = sorted({r["n"] for r in rows})
    L = ["", "**In words.**"]
    for n in sizes:
        rs = [r for r in rows if r["n"] == n]
        ks_fail = sum(r["tapered"]["ks"] > r["tapered"]["ks_crit"] for r in rs)
        L.append(f"N = {n} ({len(rs)} catalogs): slipping fraction {_span([r['slip_fraction'] for r in rs])}, "
                 f"{_span([r['events_per_block_cycle'] for r in rs], '{:.3g}')} events per block and loading cycle; "
                 f"tapered b {_span([r['tapered']['b'] for r in rs])}, KS rejects the tapered power law in {ks_fail} of "
                 f"{len(rs)}; P_c = {_span([r['moments']['cutoff'] for r in rs], '{:.3g}')} "
                 f"(P_c/N = {_span([r['moments']['cutoff'] / n for r in rs])}); largest event "
                 f"{_span([r['largest']['potency'] for r in rs], '{:.3g}')} "
                 f"({_span([r['largest']['n_blocks'] for r in rs], '{:.0f}')} blocks); spanning events "
                 f"{_span([r['span_per_cycle'] for r in rs])} per loading cycle.")
    cut = [r for r in nh["rows"] if r["cut"] == "long event"]
    if cut:
        L.append("Sliding: " + ", ".join(f"N = {r['n']} at ν = {r['nu']:g}, ν_f = {r['nu_f']:g}" for r in cut)
                 + f" had an event longer than the bound after {_span([r['events'] for r in cut], '{:.0f}')} "
                 "catalogued events: the chain slides for loading cycles, there is no event-size distribution there.")
    fits = [g["fss"]["cutoff"] for g in nh["groups"] if math.isfinite(g["fss"]["cutoff"].get("theta", math.nan))]
    if fits:
        L.append(f"The cutoff grows with N as N^{_span([-f['theta'] for f in fits])} over the (ν, ν_f) near 1/2 "
                 "(N^1 is the growth of the potency of events of a fixed fraction of the chain).")
    busy = sorted({r["n"] for r in rows if r["slip_fraction"] > MERGED})
    if busy:
        words = [g["reading"][0] for g in nh["groups"]]
        L.append(f"At N = {', '.join(map(str, busy))} the slipping fraction exceeds {MERGED:g}: a catalogued event "
                 "(it ends only when every block is stuck) sums slips all over the chain, so the growth of the "
                 "cutoff and the shapes of these distributions measure the merging of slips, not a rupture size. "
                 f"Readings: {words.count('critical-like')} critical-like, {words.count('characteristic-size')} "
                 f"characteristic-size, {words.count('undecided')} undecided of {len(words)}; telling the two "
                 "pictures apart needs events defined by connected slip, or parameters (larger ℓ, other ν) at "
                 "which the chain is mostly stuck.")
    return L


def _nu_comparison(nh) -> list:
    """The same (ν_f, N) at the two ν of the study, side by side."""
    rows = [r for r in nh["rows"] if r.get("fit")]
    nus = sorted({r["nu"] for r in rows}, reverse=True)
    if len(nus) < 2:
        return []
    hi, lo = nus[0], nus[-1]
    pairs = [(a, b) for a in rows for b in rows if a["nu"] == hi and b["nu"] == lo and
             (a["nu_f"], a["n"]) == (b["nu_f"], b["n"])]
    if not pairs:
        return []
    def ratio(f):
        return _span([f(b) / f(a) for a, b in pairs if f(a) > 0])
    L = ["", f"The same (ν_f, N) at ν = {hi:g} and ν = {lo:g} (first / second value). From ν = {hi:g} to {lo:g}, "
         f"events per loading cycle × {ratio(lambda r: r['events'] / r['cycles'])}, ⟨P⟩ × "
         f"{ratio(lambda r: r['moments']['mean'])} (the many creep events of lone blocks, ν_f > ν_f*, whose "
         f"potency is O(ν)), P_c × {ratio(lambda r: r['moments']['cutoff'])}, tapered b × "
         f"{ratio(lambda r: r['tapered']['b'])}, slipping fraction × {ratio(lambda r: r['slip_fraction'])}:", "",
         "| ν_f | N | events per cycle | 1-block events | ⟨P⟩ | P_c | tapered b | spanning per cycle | longest event (cycles) |",
         "|---|---|---|---|---|---|---|---|---|"]
    for a, b in pairs:
        def two(f, fmt):
            return f"{fmt(f(a))} / {fmt(f(b))}"
        L.append(f"| {a['nu_f']:g} | {a['n']} | {two(lambda r: r['events'] / r['cycles'], lambda x: f'{x:.3g}')} | "
                 f"{two(lambda r: r['one_block_fraction'], lambda x: f'{100 * x:.0f} %')} | "
                 f"{two(lambda r: r['moments']['mean'], lambda x: f'{x:.3g}')} | "
                 f"{two(lambda r: r['moments']['cutoff'], lambda x: f'{x:.3g}')} | "
                 f"{two(lambda r: (r['tapered']['b'], r['tapered']['b_sigma']), lambda x: _pm(*x))} | "
                 f"{two(lambda r: r['span_per_cycle'], lambda x: f'{x:.2g}')} | "
                 f"{two(lambda r: r['largest']['duration_cycles'], lambda x: f'{x:.2f}')} |")
    return L


def near_half_figure(out, nh) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    groups = nh["groups"]
    cols = min(4, len(groups) + 1)
    rows = -(-(len(groups) + 1) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.6 * cols, 3.4 * rows), squeeze=False)
    flat = axes.ravel()
    for a in flat[len(groups) + 1:]:
        a.set_visible(False)
    for ax, g in zip(flat, groups):
        for r in nh["rows"]:
            if r["nu"] != g["nu"] or r["nu_f"] != g["nu_f"] or not r.get("fit"):
                continue
            e, cnt = np.array(r["mfd"]["edges"]), np.array(r["mfd"]["counts"], dtype=float)
            mid = (e[1:] + e[:-1]) / 2
            cum = cnt[::-1].cumsum()[::-1] / max(r["cycles"], 1e-300)     # N(≥ m) per loading cycle
            ax.semilogy(mid[cum > 0], cum[cum > 0], "-", label=f"N = {r['n']}")
        ax.set(title=f"ν = {g['nu']:g}, ν_f = {g['nu_f']:g}", xlabel="m = log10 P")
        ax.legend(fontsize=6)
    for a in axes[:, 0]:
        a.set_ylabel("events with potency ≥ P, per cycle")
    ax = flat[len(groups)]
    for g in groups:
        rs = [r for r in nh["rows"] if r["nu"] == g["nu"] and r["nu_f"] == g["nu_f"] and r.get("fit")]
        if rs:
            ax.errorbar([r["n"] for r in rs], [r["moments"]["cutoff"] for r in rs],
                        yerr=[r["moments"]["cutoff_sigma"] for r in rs], fmt="o-" if g["nu"] >= 1e-3 else "s--",
                        ms=3, capsize=2, label=f"ν = {g['nu']:g}, ν_f = {g['nu_f']:g}")
    ax.set(xscale="log", yscale="log", xlabel="N", ylabel="P_c = ⟨P²⟩/⟨P⟩", title="cutoff potency against N")
    sizes = sorted({r["n"] for r in nh["rows"]})
    ax.set_xticks(sizes, [str(n) for n in sizes], minor=False)
    ax.set_xticks([], minor=True)
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


def verdict_notes(cfg, data) -> dict:
    """Evidence and words the near-1/2 catalogs and the small-ν sweep add to the verdict table:
    ``cl``/``mk``/``sak`` → (evidence sentence, verdict word or None to keep the table's own)."""
    nh, small = data.get("near_half"), data.get("sweeps_small_nu", {})
    out = {"cl": ("", None), "mk": ("", None), "sak": ("", None)}
    if nh:
        groups = [g for g in nh["groups"] if g["sizes"]]
        read = "; ".join(f"ν = {g['nu']:g}, ν_f = {g['nu_f']:g} (N = {', '.join(map(str, g['sizes']))}): "
                         f"{g['reading'][0]} ({g['reading'][1]})" for g in groups)
        cut = [r for r in nh["rows"] if r["cut"] in ("long event", "cpu")]
        cuts = ("; catalogs cut: " + ", ".join(f"ν = {r['nu']:g}, ν_f = {r['nu_f']:g}, N = {r['n']} by "
                                              f"{r['cut']} after {r['events']} events" for r in cut)) if cut else ""
        words = [g["reading"][0] for g in groups]
        why = [g["reading"][1].split(":")[0].split(";")[0] for g in groups if g["reading"][0] == "undecided"]
        top = max(set(why), key=why.count) if why else ""
        mk = ("supported" if "critical-like" in words and "characteristic-size" not in words
              else "contradicted" if words and all(w == "characteristic-size" for w in words)
              else f"undecided ({words.count('critical-like')} critical-like, "
                   f"{words.count('characteristic-size')} characteristic-size, {words.count('undecided')} undecided "
                   f"of {len(words)} (ν, ν_f) near 1/2; the most frequent reason, {why.count(top)}×: {top})")
        out["mk"] = ("Near ν_f = 1/2 (section \"Magnitude–frequency near ν_f = 1/2\"): " + read + cuts + ".", mk)
        rows = [r for r in nh["rows"] if r.get("fit")]
        ok = [r for r in rows if r["tapered"]["ks"] <= r["tapered"]["ks_crit"] and r["tapered"]["b"] > 2 * r["tapered"]["b_sigma"]]
        exc = [r for r in rows if math.isfinite(r["spanning"]["excess"]) and r["spanning"]["excess"] > 3]
        out["cl"] = (f"Near ν_f = 1/2: the tapered power law passes KS with b > 2σ in {len(ok)} of {len(rows)} catalogs"
                     + (" (" + ", ".join(f"ν = {r['nu']:g}, ν_f = {r['nu_f']:g}, N = {r['n']}: b = "
                                        f"{_pm(r['tapered']['b'], r['tapered']['b_sigma'])}" for r in ok) + ")" if ok else "")
                     + f"; spanning events above 3× the power law's extrapolation in {len(exc)}"
                     + (" (" + ", ".join(f"ν = {r['nu']:g}, ν_f = {r['nu_f']:g}, N = {r['n']}: "
                                        f"{r['spanning']['excess']:.3g}×" for r in exc) + ")" if exc else "") + ".",
                     "partly supported near ν_f = 1/2: power-law stretches with an excess of spanning events"
                     if any(r in exc for r in ok) else None)
    if small.get("table"):
        main = {r["n"]: r for r in data["sweeps"]["table"]}
        nu0, nu1 = cfg["chain"]["nu"], cfg["sweep_small_nu"]["nu"]
        cells = []
        for r in small["table"]:
            a, b = main.get(r["n"], {}).get("slip_per_block"), r["slip_per_block"]
            if a:
                cells.append(f"N = {r['n']}: {_pm(a['jump_sign'] * a['jump'], a['jump_sigma'], 3)} "
                             f"({a['jump_at'][0]:g}→{a['jump_at'][1]:g}) at ν = {nu0:g}, "
                             f"{_pm(b['jump_sign'] * b['jump'], b['jump_sigma'], 3)} ({b['jump_at'][0]:g}→{b['jump_at'][1]:g})"
                             f" at ν = {nu1:g}")
        one = next((r for r in small["table"] if r["n"] == 1), None)
        sharper = [r["n"] for r in small["table"] if one and r["n"] > 1 and r["slip_per_block"]["jump"]
                   - 2 * r["slip_per_block"]["jump_sigma"] > one["slip_per_block"]["jump"]]
        star = 0.5 / math.sqrt(1 + 2 * float(cfg["chain"]["ell"]) ** 2)
        chains = [(r, main[r["n"]]) for r in small["table"] if r["n"] > 1 and r["n"] in main]
        ratio = [b["slip_per_block"]["jump"] / a["slip_per_block"]["jump"] for b, a in chains]
        near = [b["n"] for b, _ in chains if min(abs(x - star) for x in b["slip_per_block"]["jump_at"]) <= 0.1]
        word = None
        if chains:
            word = ("undecided: at ν = " + f"{nu1:g}" + " the chains' largest change of D ("
                    + ", ".join(f"N = {b['n']}: {_pm(b['slip_per_block']['jump'], b['slip_per_block']['jump_sigma'], 3)} "
                                f"at {b['slip_per_block']['jump_at'][0]:g}→{b['slip_per_block']['jump_at'][1]:g}"
                                for b, _ in chains)
                    + f") is {min(ratio):.1f}–{max(ratio):.1f}× the change at ν = {nu0:g}"
                    + (f", next to the lone-block threshold ν_f* = {star:.3f} (N = {', '.join(map(str, near))}): the "
                       "small events' transition sharpens as ν decreases, as a first-order one does" if near else "")
                    + f"; at ν = {nu1:g} only N ≤ {max(b['n'] for b, _ in chains)} was run, too few sizes for a "
                    "finite-size trend")
        out["sak"] = (f"Largest change of D at ν = {nu1:g} against {nu0:g} (section \"The sweep at ν = {nu1:g}\"; "
                      f"the lone-block threshold is ν_f* = {star:.3f}, the uniform mode's 1/2): "
                      + "; ".join(cells) + f"; chains changing more sharply than the single block at ν = {nu1:g}: "
                      + (", ".join(f"N = {n}" for n in sharper) or "none") + ".", word)
    return out
