"""Text of the chain report's near-1/2 magnitude–frequency section, of the small-ν sweep and their
evidence for the verdict table (data from ``_study_mfd``; every number comes from ``data``)."""

from __future__ import annotations

import math

from ...report.document import Figure, Paragraph, Section, Table
from ._study_csn import CSN_RULES, csn_cell, csn_word
from .scaling import MERGED

__all__ = ["near_half_section", "small_nu_section", "verdict_notes"]


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
    sizes = f"N = {', '.join(str(int(n)) for n in f['sizes'])}"
    if f["dof_power"] < 1:      # two sizes: the line passes through both points, there is no χ² to judge it by
        return f"∝ N^{-f['theta']:.2f}±{f['theta_sigma']:.2f} (2 sizes, no χ²; {sizes})"
    r = f["chi2_power"] / f["dof_power"]
    # σ from the weights alone; where the scatter exceeds the error bars, the σ scaled by √(χ²/dof) beside it
    scaled = f", σ×√(χ²/dof) = {f['theta_sigma'] * math.sqrt(r):.2f}" if r > 1 else ""
    return f"∝ N^{-f['theta']:.2f}±{f['theta_sigma']:.2f} (χ²/dof {r:.1f}{scaled}; {sizes})"


def near_half_section(cfg, nh) -> list:
    """The report section (typed blocks)."""
    c = cfg["near_half"]
    B = [Paragraph(
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
         "(scaling.tapered_gr). Power law tested by " + CSN_RULES + ". Cutoff: P_c = ⟨P²⟩/⟨P⟩ over all events, σ by 10 batch "
         "means (scaling.moment_cutoff; docs/chain.md \"Cutoff and finite-size scaling\"). Spanning: "
         "n_blocks = N, σ = √k/events. Slipping fraction: Σ duration / elapsed time; an event ends only when "
         "the whole chain is stuck, so where this is near 1 one catalogued event holds many separate slips "
         "(the events per block and loading cycle fall with N) and its potency adds them up."),
         Figure("fig_mfd_half.png", "Events with potency ≥ P per loading cycle against m = log10 P, one panel per "
                "(ν, ν_f), one line per N with ≥ 20 events (whole catalogued events); last panel: the cutoff "
                "P_c = ⟨P²⟩/⟨P⟩ against N "
                "(± batch-means σ), solid ν = 0.001, dashed ν = 0.0001.", alt="mfd near 1/2")]
    rows = []
    for r in nh["rows"]:
        head = [f"{r['nu']:g}", f"{r['nu_f']:g}", f"{r['n']}", f"{r['cycles']:.1f} ({r['cycles_asked']:g})",
                f"{r['events']}", f"{r['cut']}"]
        if not r.get("fit"):
            rows.append([*head, "fewer than 20 events", *[""] * 9, f"{r['cpu']:.0f}"])
            continue
        f, t, m, lg = r["fit"], r["tapered"], r["moments"], r["largest"]
        rows.append([*head, f"{_pm(f['b'], f['sigma'])} [{f['m_min']:.1f}, {f['m_max']:.1f}]", _pm(t["b"], t["b_sigma"]),
                     _g(t["corner"], t["corner_sigma"]), csn_cell(r.get("csn")),
                     f"{lg['potency']:.3g} ({lg['n_blocks']}, {lg['duration_cycles']:.2f})", _g(m["mean"], m["mean_sigma"]),
                     _g(m["cutoff"], m["cutoff_sigma"]), f"{r['span_count']}, {r['span_fraction']:.2g} "
                     f"({r['span_per_cycle']:.2g})", f"{r['spanning']['excess']:.3g}", f"{r['slip_fraction']:.2f} "
                     f"({r['events_per_block_cycle']:.3g})", f"{r['cpu']:.0f}"])
    B += [Table(["ν", "ν_f", "N", "cycles (asked)", "events", "cut", "b (Page) [m range]", "tapered b", "P_corner",
                 "CSN (multi-block events)", "largest P (n_blocks, cycles)", "⟨P⟩", "P_c = ⟨P²⟩/⟨P⟩",
                 "spanning: count, fraction (per cycle)", "excess over GR",
                 "slipping fraction (events per block and cycle)", "CPU s"], rows),
          Paragraph("Finite-size fits over N (analysis.finite_size_fit, power law y = A N^a with a = −θ, weighted on "
          "ln y, σ of the exponent from the points' error bars; where χ²/dof > 1 that σ scaled by √(χ²/dof) is given "
          "beside it, and a χ²/dof far above 1 means the points scatter about the power law far beyond their errors, "
          "so the exponent is a mean slope, not a scaling law; spanning fraction over the sizes with at least one "
          "spanning event) and the reading "
          "(scaling.mfd_reading: *critical-like* = the cutoff grows with N, every N has a CSN power-law stretch "
          "(the power law plausible over ≥ 1 decade), the tapered b is > 0 "
          "and the same at every N, and no N has a spanning excess; *characteristic-size* = an exponential law (b ≈ 0) "
          "at the largest N, or spanning events in excess of the power law with a spanning fraction that "
          "does not decrease with N):"),
          Table(["ν", "ν_f", "cutoff P_c", "mean ⟨P⟩", "spanning fraction", "reading"], _group_rows(nh["groups"]))]
    B += _summary(nh) + _patch_section(nh) + _nu_comparison(nh)
    return [Section("Magnitude–frequency near ν_f = 1/2 and its finite-size scaling", B)]


def _group_rows(groups) -> list:
    return [[f"{g['nu']:g}", f"{g['nu_f']:g}", _law(g["fss"]["cutoff"]), _law(g["fss"]["mean"]), _law(g["fss"]["span"]),
             f"**{g['reading'][0]}**: {g['reading'][1]}"] for g in groups]


def _patch_section(nh) -> list:
    """The same catalogs cut into connected slip patches (scaling.slip_clusters)."""
    rows = [r for r in nh.get("patch_rows", []) if r.get("fit")]
    if not rows:
        return []
    events = {(r["nu"], r["nu_f"], r["n"]): r["events"] for r in nh["rows"]}
    B = [Paragraph(
         "Each catalogued event cut into its connected slip patches: runs of adjacent blocks that moved "
         "(U_j(end) − U_j(start) > 0), separated by blocks that did not (scaling.slip_clusters; a stuck block "
         "transmits no slip, so two patches never interacted within the event). A patch has the potency and "
         "block count of its run; a patch of N blocks spans the chain. Slips at the same place at different "
         "times of one event still add up in one patch. The same statistics, fits and rules as above, "
         "without the merged-events rule:"),
         Table(["ν", "ν_f", "N", "events → patches", "b (Page)", "tapered b", "P_corner", "CSN (multi-block patches)",
                "largest patch P (blocks)", "P_c = ⟨P²⟩/⟨P⟩", "spanning patches per cycle", "excess over GR"],
               [[f"{r['nu']:g}", f"{r['nu_f']:g}", f"{r['n']}", f"{events[(r['nu'], r['nu_f'], r['n'])]} → {r['events']}",
                 _pm(r["fit"]["b"], r["fit"]["sigma"]), _pm(r["tapered"]["b"], r["tapered"]["b_sigma"]),
                 _g(r["tapered"]["corner"], r["tapered"]["corner_sigma"]),
                 csn_cell(r.get("csn")),
                 f"{r['largest']['potency']:.3g} ({r['largest']['n_blocks']})",
                 _g(r["moments"]["cutoff"], r["moments"]["cutoff_sigma"]), f"{r['span_per_cycle']:.2g}",
                 f"{r['spanning']['excess']:.3g}"] for r in rows]),
         Paragraph("In words, per N over the (ν, ν_f) near 1/2: " + "; ".join(
        f"N = {n}: tapered b {_span([r['tapered']['b'] for r in rs])}, CSN: {_words(rs)}, P_c = "
        f"{_span([r['moments']['cutoff'] for r in rs], '{:.3g}')}, largest patch "
        f"{_span([r['largest']['potency'] for r in rs], '{:.3g}')} ({_span([r['largest']['n_blocks'] for r in rs], '{:.0f}')} "
        f"blocks), spanning patches {_span([r['span_per_cycle'] for r in rs])} per cycle"
        for n in sorted({r["n"] for r in rows}) for rs in [[r for r in rows if r["n"] == n]]) + "."),
         Table(["ν", "ν_f", "patch cutoff P_c", "mean patch ⟨P⟩", "spanning fraction", "reading"],
               _group_rows(nh["patch_groups"]))]
    return [Section("By connected slip patches", B, level=3)]


def _words(rows) -> str:
    """How many of ``rows`` the CSN test reads each way (csn_word), e.g. '3 ruled out, 1 no scaling range of 4'."""
    words = [csn_word(r.get("csn")) for r in rows]
    return ", ".join(f"{words.count(w)} {w}" for w in ("ruled out", "undecided", "plausible", "no scaling range",
                                                        "no fit") if words.count(w)) + f" of {len(words)}"


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
    L = ["**In words.**"]
    for n in sizes:
        rs = [r for r in rows if r["n"] == n]
        L.append(f"N = {n} ({len(rs)} catalogs): slipping fraction {_span([r['slip_fraction'] for r in rs])}, "
                 f"{_span([r['events_per_block_cycle'] for r in rs], '{:.3g}')} events per block and loading cycle; "
                 f"tapered b {_span([r['tapered']['b'] for r in rs])}; CSN: {_words(rs)}; P_c = {_span([r['moments']['cutoff'] for r in rs], '{:.3g}')} "
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
                 f"characteristic-size, {words.count('undecided')} undecided of {len(words)}"
                 + ("; the patches below cut each event at the blocks that did not move." if nh.get("patch_rows")
                    else "; telling the two pictures apart needs events defined by connected slip."))
    return [Paragraph("\n".join(L))]


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
    head = (f"The same (ν_f, N) at ν = {hi:g} and ν = {lo:g} (first / second value). From ν = {hi:g} to {lo:g}, "
         f"events per loading cycle × {ratio(lambda r: r['events'] / r['cycles'])}, ⟨P⟩ × "
         f"{ratio(lambda r: r['moments']['mean'])} (the many creep events of lone blocks, ν_f > ν_f*, whose "
         f"potency is O(ν)), P_c × {ratio(lambda r: r['moments']['cutoff'])}, tapered b × "
         f"{ratio(lambda r: r['tapered']['b'])}, slipping fraction × {ratio(lambda r: r['slip_fraction'])}:")
    rows = []
    for a, b in pairs:
        def two(f, fmt):
            return f"{fmt(f(a))} / {fmt(f(b))}"
        rows.append([f"{a['nu_f']:g}", f"{a['n']}", two(lambda r: r["events"] / r["cycles"], lambda x: f"{x:.3g}"),
                     two(lambda r: r["one_block_fraction"], lambda x: f"{100 * x:.0f} %"),
                     two(lambda r: r["moments"]["mean"], lambda x: f"{x:.3g}"),
                     two(lambda r: r["moments"]["cutoff"], lambda x: f"{x:.3g}"),
                     two(lambda r: (r["tapered"]["b"], r["tapered"]["b_sigma"]), lambda x: _pm(*x)),
                     two(lambda r: r["span_per_cycle"], lambda x: f"{x:.2g}"),
                     two(lambda r: r["largest"]["duration_cycles"], lambda x: f"{x:.2f}")])
    return [Paragraph(head), Table(["ν_f", "N", "events per cycle", "1-block events", "⟨P⟩", "P_c", "tapered b",
                                    "spanning per cycle", "longest event (cycles)"], rows)]


def small_nu_section(cfg, small, main) -> list:
    """D (up branch) per ν_f at the small ν beside the main ν for the same N, and jump / loop width."""
    nu0, nu1 = cfg["chain"]["nu"], cfg["sweep_small_nu"]["nu"]
    grid = small["table"][0]["nu_f"]
    B = [Paragraph(
         f"The same ν_f sweep (up, then down) at ν = {nu1:g} for the small chains "
         f"(`[sweep_small_nu]`: N = {', '.join(str(r['n']) for r in small['table'])}, seeds "
         f"{', '.join(str(r['seeds']) for r in small['table'])}, steps of "
         f"{', '.join(f'{x:g}' for x in cfg['sweep_small_nu']['cycles_per_step'])} loading cycles). D on the up branch "
         "(mean ± standard error over seeds); the single block's D → 0 for ν_f > 1/2 and a lone block's slip → 0 "
         "above ν_f* as ν → 0, so the curves sharpen where they are first-order-like:")]
    rows = []
    by_n = {r["n"]: r for r in main["table"]}
    for r in small["table"]:
        for nu, row in ((nu0, by_n.get(r["n"])), (nu1, r)):
            if row is None:
                continue
            d = row["slip_per_block"]
            cells = [_pm(d["up"][row["nu_f"].index(x)], d["se_up"][row["nu_f"].index(x)], 3)
                     if x in row["nu_f"] and math.isfinite(d["up"][row["nu_f"].index(x)]) else "" for x in grid]
            rows.append([f"{r['n']}", f"{nu:g}", *cells,
                         f"{_pm(d['jump_sign'] * d['jump'], d['jump_sigma'], 3)} ({d['jump_at'][0]:g}→{d['jump_at'][1]:g})",
                         f"{_pm(d['width'], d['width_sigma'], 3)} ({d['width_at']:g})", f"{row['events']}",
                         f"{row['seconds']:.0f}"])
    B.append(Table(["N", "ν", *(f"{x:g}" for x in grid), "D jump (at)", "D loop width (at)", "events", "CPU s"], rows))
    return [Section(f"The sweep at ν = {nu1:g} against ν = {nu0:g}", B, level=3)]


def verdict_notes(cfg, data) -> dict:
    """Evidence and words the near-1/2 catalogs and the small-ν sweep add to the verdict table:
    ``cl``/``mk``/``sak`` → (evidence sentence, verdict word or None to keep the table's own)."""
    nh, small = data.get("near_half"), data.get("sweeps_small_nu", {})
    out = {"cl": ("", None), "mk": ("", None), "sak": ("", None)}
    if nh:
        by_patch = bool(nh.get("patch_groups"))
        groups = [g for g in nh["patch_groups" if by_patch else "groups"] if g["sizes"]]
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
        ev = [g["reading"][0] for g in nh["groups"] if g["sizes"]]
        busy = sorted({r["n"] for r in nh["rows"] if r.get("fit") and r["slip_fraction"] > MERGED})
        out["mk"] = ("Near ν_f = 1/2 (section \"Magnitude–frequency near ν_f = 1/2\"), "
                     + ("by connected slip patches: " if by_patch else "") + read + cuts
                     + (f". By whole-chain events: {ev.count('critical-like')} critical-like, "
                        f"{ev.count('characteristic-size')} characteristic-size, {ev.count('undecided')} undecided"
                        + (f" (slipping fraction above {MERGED:g} at N = {', '.join(map(str, busy))}: events merge "
                           "separate slips)" if busy else "") if by_patch else "") + ".", mk)
        rows = [r for r in nh["patch_rows" if by_patch else "rows"] if r.get("fit")]
        from .scaling import _power_stretch

        ok = [r for r in rows if _power_stretch(r) and r["tapered"]["b"] > 2 * r["tapered"]["b_sigma"]]
        exc = [r for r in rows if math.isfinite(r["spanning"]["excess"]) and r["spanning"]["excess"] > 3]
        out["cl"] = (f"Near ν_f = 1/2{', by connected slip patches' if by_patch else ''}: a CSN power-law stretch "
                     f"(plausible over ≥ 1 decade) with tapered b > 2σ in {len(ok)} of {len(rows)} catalogs"
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
                    + f") is {_span(ratio, '{:.1f}')}× the change at ν = {nu0:g}"
                    + (f", next to the lone-block threshold ν_f* = {star:.3f} (N = {', '.join(map(str, near))})"
                       if near else "")
                    + (": the change sharpens as ν decreases, as a jump rounded by ν does (a continuous change "
                       "rounded by ν sharpens too)" if min(ratio) > 1
                       else ": it does not sharpen as ν decreases" if max(ratio) <= 1 else "")
                    + f"; at ν = {nu1:g} only N ≤ {max(b['n'] for b, _ in chains)} was run, too few sizes for a "
                    "finite-size trend")
        out["sak"] = (f"Largest change of D at ν = {nu1:g} against {nu0:g} (section \"The sweep at ν = {nu1:g}\"; "
                      f"the lone-block threshold is ν_f* = {star:.3f}, the uniform mode's 1/2): "
                      + "; ".join(cells) + f"; chains changing more sharply than the single block at ν = {nu1:g}: "
                      + (", ".join(f"N = {n}" for n in sharper) or "none") + ".", word)
    return out
