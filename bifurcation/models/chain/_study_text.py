"""Text of the chain report (``study.main``): every number in it comes from ``data`` (data.json)."""

from __future__ import annotations

import math

from ...report.document import Figure, Paragraph, Section, Table

__all__ = ["FSS_RULES", "chi2_p", "fss_words", "report_blocks"]


def _pm(x, s, d=3) -> str:
    if not math.isfinite(x):
        return "–"
    return f"{x:.{d}f} ± {s:.{d}f}" if math.isfinite(s) else f"{x:.{d}f}"


def chi2_p(chi2: float, dof: int) -> float:
    """P(χ² ≥ chi2) for ``dof`` degrees of freedom: the goodness-of-fit test of a weighted least-squares fit."""
    import mpmath

    if dof < 1 or not math.isfinite(chi2):
        return math.nan
    return float(mpmath.gammainc(dof / 2, chi2 / 2, mpmath.inf, regularized=True))


def fss_words(f: dict) -> tuple[str, str]:
    """(short verdict, sentence) for a finite-size fit of ``analysis.finite_size_fit``.

    Rules (FSS_RULES): θ more than 2σ above 0 with the constant rejected by its χ² test (p < 0.05) →
    vanishes; |θ| ≤ 2σ with the constant not rejected → persists, unless θ + 2σ > 0.25 (a slow decay not
    excluded) → undecided; θ more than 2σ below 0 → grows; otherwise undecided. (χ²/dof > 2 was the
    rejection before: with 3 sizes of 4 that is p ≈ 0.075, not a rejection at 5 %.)
    """
    if f["points"] < 3 or not math.isfinite(f["theta"]):
        return "undecided", f"only {f['points']} sizes with a non-zero value: no fit"
    th, s = f["theta"], f["theta_sigma"]
    rc = f["chi2_constant"] / max(f["dof_constant"], 1)
    rp = f["chi2_power"] / max(f["dof_power"], 1)
    pc = chi2_p(f["chi2_constant"], f["dof_constant"])
    fits = (f"θ = {th:.2f} ± {s:.2f} (χ²/dof {rp:.1f}); constant {f['constant']:.3g} ± "
            f"{f['constant_sigma']:.2g} (χ²/dof {rc:.1f}, p = {pc:.2g}), "
            f"N = {', '.join(str(int(n)) for n in f['sizes'])}")
    rejected = pc < 0.05
    if th > 2 * s and rejected:
        return "vanishes", "decreases with N: " + fits
    if th < -2 * s:
        return "grows", "grows with N: " + fits
    if th > 2 * s:
        return "undecided", "decreases with N, but a constant is not rejected (χ² p ≥ 0.05): " + fits
    if not rejected:
        if th + 2 * s > 0.25:
            return "undecided", ("compatible with a constant, but a decay as fast as N^-%.2f is not excluded: "
                                 % (th + 2 * s)) + fits
        return "persists", "compatible with a constant: " + fits
    return "undecided", "no trend in N beyond 2σ, yet a constant is rejected (χ² p < 0.05): " + fits


FSS_RULES = ("**vanishes**: θ more than 2σ above 0 and the constant rejected by its χ² test (p < 0.05, p given "
             "beside its χ²/dof); **grows**: θ more than 2σ below 0; **persists**: |θ| ≤ 2σ, the constant not "
             "rejected and θ + 2σ ≤ 0.25; **undecided** otherwise (the reason is said)")


def report_blocks(cfg, path, data, wall, speed: list) -> list:
    """The report as typed blocks (``report.document``); ``speed``: the blocks of a "## Speed" section
    carried over from an earlier REPORT.md (none if empty)."""
    from ...report.document import Heading, Paragraph

    from ._study_transition import transition_stats

    c, sw = cfg["chain"], data["sweeps"]
    data = {**data, "transition": data.get("transition") or transition_stats(data)}   # computed once per rendering
    ell = float(c["ell"])
    star = 0.5 / math.sqrt(1 + 2 * ell**2)
    B = [Heading("Burridge–Knopoff chains, event-exact: report", 1), Paragraph(
         f"Produced by `bifurcation study chain {path}` in {wall:.0f} s of wall "
         f"time on {cfg['study'].get('workers', 2)} worker processes"
         + (f", {data['cpu_seconds']:.0f} CPU seconds in all (5-minute load average "
            f"{data['load_average']:.1f} at the end"
            + (": other jobs shared the cores, so the wall time is longer than an idle run's)"
               if data["load_average"] > 2.5 else ")")
            if "cpu_seconds" in data else "") + " (model and algorithm: docs/chain.md; the "
         "definitions used here: docs/chain.md, \"Order parameter and hysteresis\"). Law " + c["law"] +
         f", ℓ = {ell:g}, ν = {c['nu']:g}, {c['ends']} ends, random start of amplitude {c['amplitude']}. "
         "Event sequences are chaotic (docs/chain.md, Precision), so digits of individual events of the "
         "sweeps and catalogs depend on the CPU's rounding; the statistics do not, within their errors. "
         "All numbers: [data.json](data.json)."
         + (" The sections before \"Published parameter sets\" come from that full run; the preset catalogs and "
            "the verdict table were added by `--presets-only` (same workflow, its `[presets]` section)."
            if data.get("presets_wall_seconds") else "")
         + (" The verdict table's column \"at the preset's own ν\" is read from the `subevents_*.json` of this "
            "directory, written by `--published-nu-only` (same workflow, its `[published_nu]` section; catalogs and "
            "fits: [PUBLISHED_NU.md](PUBLISHED_NU.md)). The CSN fits of the report's own catalogs are kept in "
            "csn.json, keyed by the data they fit (recomputed from catalogs.npz and near_half.npz by "
            "tests/test_chain_report_csn.py)." if data.get("published_nu") else "")
         + (" The section \"ℓ scan\" is read from ell_scan.json, written run by run by `--ell-scan-only` (same "
            "workflow, its `[ell_scan]` section)." if (data.get("ell_scan") or {}).get("rows") else ""))]
    B += _threshold_section(data, c)
    B += _order_section(cfg, data, sw, star)
    from ._study_mfd_text import near_half_section, small_nu_section

    if data.get("sweeps_small_nu", {}).get("table"):
        B += small_nu_section(cfg, data["sweeps_small_nu"], sw)
    if data.get("ell_scan"):
        from ._study_ell import ell_scan_section

        B += ell_scan_section(cfg, data["ell_scan"])
    B += _mfd_section(data)
    if data.get("near_half"):
        B += near_half_section(cfg, data["near_half"])
    B += speed
    readings = _verdict(cfg, data, sw, star)
    from ._study_presets import preset_section, verdict_table

    rows = readings[0].rows     # the last cell of each claim's row: its verdict
    cell = (lambda i: rows[i][-1] if len(rows) > i else "–")
    B += preset_section(data)
    B += verdict_table(cfg, data, {"vas": "see \"Readings of the σ = 0, ℓ = 1 runs\" below",
                                   "vas_word": cell(0), "sak": cell(3)})
    B.append(Section("Readings of the σ = 0, ℓ = 1 runs, claim by claim (the seed's friction at ℓ = 1: the claims' "
                     "own models only for Vasconcelos' family; the verdicts are in the table above)", readings))
    return B


def _threshold_section(data, c) -> list:
    th = data["threshold"]
    nus = [r["nu"] for r in th[0]["rows"]]
    rows = []
    for t in th:
        r0 = t["rows"][-1]
        rows.append([f"{t['ell']:g}", "free end" if t["end"] else "interior", f"{r0['k']:g}", f"{r0['nu_f_star']:.5f}",
                     *(f"{r['nu_f_cross']:.5f} ({100 * r['relative_offset']:+.2f} %)" for r in t["rows"]),
                     f"{r0['delta_below']:.3g} / {r0['delta_above']:.2e}"])
    offs = [abs(t["rows"][-1]["relative_offset"]) for t in th]
    # creep side: k·P = Δ(ν/√k, ·) ∝ ν/√k, so the curves part by √k there; the spread and √k's, from the table
    above = [t["rows"][-1]["delta_above"] for t in th]
    ks = [t["rows"][-1]["k"] for t in th]
    below = [t["rows"][-1]["delta_below"] for t in th]
    B = [Paragraph(
         "A block slipping alone among stuck neighbours has stiffness k = 1 + 2ℓ² (interior) or 1 + ℓ² (free "
         "end); docs/chain.md derives ν_f* = 1/(2√k). Measured on the chain engine (threshold.py: the one "
         "loaded block of an N = 5 or N = 3 chain, no rescaling used): the ν_f where k·P falls through "
         f"{th[0]['rows'][0]['level']} (k·P is O(1) in stick-slip, O(ν) in creep), by bisection."),
         Table(["ℓ", "block", "k", "ν_f*", *(f"crossing at ν = {nu:g} (offset)" for nu in nus),
                f"k·P at 0.8 ν_f* / 1.25 ν_f* (ν = {nus[-1]:g})"], rows),
         Paragraph(f"The crossing lies above ν_f* and closes on it as ν decreases (largest offset at ν = {nus[-1]:g}: "
                   f"{100 * max(offs):.2f} %), like the single block's own transition at ν_f = 1/2, which finite ν "
                   "smooths towards larger ν_f (docs/physics.md). The curves k·P against ν_f/ν_f* fall on one "
                   f"curve below ν_f* for every ℓ and both ends (k·P at 0.8 ν_f* = "
                   + (f"{min(below):.3g}" if f"{min(below):.3g}" == f"{max(below):.3g}"
                      else f"{min(below):.3g}–{max(below):.3g}") + ": "
                   "the single block's Δ); above it, in creep, k·P is the single block's Δ at ν/√k, O(ν/√k), so the "
                   f"curves part by √k there (at 1.25 ν_f* and ν = {nus[-1]:g}: "
                   f"{min(above):.3g}–{max(above):.3g}, a factor "
                   f"{max(above) / min(above):.2f}, against √k's {math.sqrt(max(ks) / min(ks)):.2f}):"),
         Figure("fig_threshold.png", "k·P of the one slipping block against ν_f/ν_f* for each ℓ and end, at the "
                "ν in the figure's title; gray: ν_f = ν_f*.", alt="threshold")]
    cats = data["catalogs"]
    if cats:
        rows = []
        for s in cats:
            o = s["one_block"]
            dev = max((o[k]["max_rel_dev"] for k in ("interior", "end") if o[k]["count"]), default=math.nan)
            rows.append([f"{s['n']}", f"{s['nu_f']}", f"{o['interior']['count']} / {o['end']['count']}",
                         f"{o['interior']['closed_form']:.6g} / {o['end']['closed_form']:.6g}", f"{dev:.1e}"])
        B += [Paragraph("Inside the catalogs below, every event that involves one block only starts stuck at σ = 1 "
                        "with stuck neighbours, so its potency must be the closed form Δ(ν/√k, √k ν_f)/k of the "
                        "single-block engine:"),
              Table(["N", "ν_f", "1-block events interior / end", "closed form P interior / end",
                     "largest relative deviation"], rows)]
    return [Section("Lone-block threshold", B)]


def _order_section(cfg, data, sw, star) -> list:
    scfg = cfg["sweep"]
    B = [Paragraph(
         "Each ν_f step lasts until the driver has advanced by ν ΔT ≥ " +
         ", ".join(f"{x:g}" for x in sorted(set(scfg["cycles_per_step"]))) +
         " units of slip per block (loading cycles; `cycles_per_step` per N in the workflow), after a "
         f"transient of {scfg['transient_cycles']} cycles at the first ν_f. Two order parameters "
         "(docs/chain.md): **D** = ΣP/Σn_blocks, the mean slip of a block in an event it takes part in "
         "(the single block's Δ at N = 1: O(1) in stick-slip, O(ν) in creep), and **Ψ** = slip carried by "
         "system-spanning events / (N ν ΔT). Mean over seeds ± standard error (seed-to-seed spread / √seeds). "
         f"Gray lines: the lone-block threshold ν_f* = {star:.4f} (solid) and the uniform mode's 1/2 (dotted)."),
         Figure("fig_order.png", alt="order parameter"),
         Table(["N", "seeds", "events", "shortest step (cycles)", "closure ΣP/(NνΔT) min – max",
                "largest slipping fraction of a step", "longest event (cycles)", "CPU seconds"],
               [[f"{r['n']}", f"{r['seeds']}", f"{r['events']}", f"{r['cycles_min']:.2f}",
                 f"{r['closure'][0]:.2f} – {r['closure'][1]:.2f}", f"{r.get('slip_fraction_max', math.nan):.2f}",
                 f"{r.get('longest_event', math.nan):.2f}", f"{r['seconds']:.0f}"] for r in sw["table"]])]
    lim = sw.get("longest_event_limit", 0.5)
    merged = ", ".join(f"N = {r['n']}: {r['merged_steps']}" for r in sw["table"] if r.get("merged_steps"))
    B.append(Paragraph(
          "The slipping fraction is the share of a step's time during which some block slips: at ν = "
          f"{cfg['chain']['nu']:g} a chain of N ≳ 16 is all stuck only part of the time, so one catalogued event (all blocks "
          "stuck again at its end, docs/chain.md) can hold several separate slips; D still counts each block's "
          "slip once as long as no block slips twice in an event. Where an event lasts longer than "
          f"{lim:g} loading cycles, blocks reload and slip again inside it (the chain slides for cycles) and D "
          "measures that event, not a block's slip: D is left out at those steps (blank in the tables, "
          f"not in the fits; steps left out: {merged or 'none'}). Ψ is kept: it is 1 for a chain sliding as one "
          "whether that is stick-slip or steady sliding, which is why D and the slipping fraction are "
          "reported with it."))
    for key, name in (("slip_per_block", "D"), ("psi", "Ψ")):
        grid = max((r["nu_f"] for r in sw["table"]), key=len)
        rows = []
        for r in sw["table"]:
            d = r[key]
            for br in ("up", "down"):
                cells = [_pm(v, s, 3) if v == v else "" for v, s in zip(d[br], d["se_" + br])]
                cells += [""] * (len(grid) - len(cells))
                rows.append([f"{r['n']}", br, *cells])
        B += [Paragraph(f"{name} per ν_f (up / down):"), Table(["N", "branch", *(f"{x:g}" for x in grid)], rows)]
    rows = []
    for r in sw["table"]:
        cells = [f"{r['n']}"]
        for key in ("slip_per_block", "psi"):
            d = r[key]
            cells += [f"{_pm(d['jump_sign'] * d['jump'], d['jump_sigma'])} ({d['jump_at'][0]:g}→{d['jump_at'][1]:g})",
                      f"{_pm(d['width'], d['width_sigma'])} ({d['width_at']:g})", _pm(d["area"], d["area_sigma"], 4)]
        rows.append(cells)
    B += [Paragraph("Jump (largest change between neighbouring ν_f on the up branch), loop width (largest "
                    "|up − down|, biased up by about one σ where there is no loop) and loop area Σ(down − up)Δν_f:"),
          Table(["N", "D jump (at ν_f)", "D width (at)", "D area", "Ψ jump (at)", "Ψ width (at)", "Ψ area"], rows)]
    rows = []
    for k, f in sw["fss"].items():
        name = k.replace("slip_per_block", "D").replace("psi", "Ψ").replace(".", " ")
        verdict, words = fss_words(f)
        rows.append([name, f"**{verdict}**: {words}"])
    B.append(Section("Finite-size scaling", [
        Paragraph("Fits of the grid readings above (the largest change between neighbouring ν_f, the loop width): "
                  "y(N) = A N^-θ (weighted least squares on ln y) against y = constant, over the chains "
                  "(N > 1; N = 1 is deterministic and has no loop by construction: every event starts from the same "
                  "state). analysis.finite_size_fit; rules for the words (_study_text.fss_words): " + FSS_RULES
                  + ". The jump's place moves "
                  "from interval to interval with N, so its fit follows no one transition: the next subsection "
                  "locates one."),
        Figure("fig_fss.png", "Jump (circles) and loop width (squares) of D (left) and Ψ (right) against N "
               "for the chains (N > 1), ± standard error over seeds; solid: the fit A N^−θ, dotted: the constant "
               "fit.", alt="fss"), Table(["quantity", "reading"], rows)], level=3))
    from ._study_transition import transition_section

    B += transition_section(data["transition"])
    return [Section("Order parameter and hysteresis (ν_f up, then down, within one run)", B)]


def _mfd_section(data) -> list:
    from ._study_csn import CSN_RULES, csn_cell

    rows = []
    for s in data["catalogs"]:
        f, sp, rl, rs = s["fit"], s["spanning"], s["recurrence_large"], s["recurrence_spanning"]
        rows.append([f"{s['n']}", f"{s['nu_f']}", f"{s['events']}", _pm(f["b"], f["sigma"], 2),
                     f"[{f['m_min']:.2f}, {f['m_max']:.2f}] ({f['n']})", csn_cell(s.get("csn")),
                     f"{sp['spanning']} ({sp['expected']:.2g}, {sp['excess']:.3g})", f"{100 * s['large_fraction']:.1f} %",
                     f"{rl['mean']:.4g}, {rl['cv']:.2f}", f"{rs['mean']:.4g}, {rs['cv']:.2f}"])
    return [Section("Magnitude–frequency", [
        Paragraph("m = log10 P. b (Page): maximum likelihood for a Gutenberg–Richter law truncated to a fixed range "
                  "(Page's estimator, analysis.b_value; σ from the Fisher information), over the multi-block events "
                  "(the 1-block events form an atom at the closed-form potency above) from the most populated "
                  "0.1-bin of m (maximum curvature) to just below the smallest system-spanning event (or the "
                  "largest event): a slope over that range, not a test that the range is a power law. Whether it is: "
                  + CSN_RULES + ". Spanning excess: observed system-spanning events over the Page fit's extrapolation "
                  "N(≥ m_span). Large events: n_blocks ≥ N/2. The raw catalogs are in catalogs.npz (the CSN fits in "
                  "csn.json, recomputed from them by tests/test_chain_report_csn.py)."),
        Figure("fig_mfd.png", "Left: events per 0.1 in m = log10 P (all events, the 1-block atom included) for each "
               "catalog, dashed: the Page fit over its fit range (a Gutenberg–Richter law truncated to that range); "
               "right: the potency in each bin of m.", alt="mfd"),
        Table(["N", "ν_f", "events", "b (Page)", "fit range m (n)", "CSN (multi-block events)",
               "spanning (expected, excess)", "large events", "recurrence of large: mean, CV",
               "of spanning: mean, CV"], rows)])]


def _verdict(cfg, data, sw, star) -> list:
    from ._study_mfd_text import verdict_notes

    notes = verdict_notes(cfg, data)
    fss, nu = sw["fss"], cfg["chain"]["nu"]
    vw, ww = fss_words(fss["slip_per_block.width"])
    th, cats, table = data["threshold"], data["catalogs"], sw["table"]
    offs = ", ".join(f"ℓ = {t['ell']:g} {'end' if t['end'] else 'interior'} {100 * t['rows'][-1]['relative_offset']:+.1f} %"
                     for t in th)
    dev = max((s["one_block"][k]["max_rel_dev"] for s in cats for k in ("interior", "end")
               if s["one_block"][k]["count"]), default=math.nan)
    first, last = [t["rows"][0]["relative_offset"] for t in th], [t["rows"][-1]["relative_offset"] for t in th]
    lone = ("**confirmed**" if all(0 < b < a for a, b in zip(first, last)) and max(last) < 0.05
            else "**not confirmed** (see the threshold table)")
    jumps = "; ".join(f"N = {r['n']}: {_pm(r['slip_per_block']['jump_sign'] * r['slip_per_block']['jump'], r['slip_per_block']['jump_sigma'])}"
                      f" ({r['slip_per_block']['jump_at'][0]:g}→{r['slip_per_block']['jump_at'][1]:g})" for r in table)
    loops = [(r["n"], r["slip_per_block"]["width"], r["slip_per_block"]["width_sigma"]) for r in table if r["n"] > 1]
    sig = [n for n, w, s in loops if w > 2 * s]
    loop_txt = "; ".join(f"N = {n}: {_pm(w, s)}" for n, w, s in loops)
    # the width is a maximum over noisy differences (biased up by ~1σ); the signed area is not: it decides
    areas = [(r["n"], r["slip_per_block"]["area"], r["slip_per_block"]["area_sigma"]) for r in table if r["n"] > 1]
    area_txt = "; ".join(f"N = {n}: {_pm(x, s, 4)}" for n, x, s in areas)
    asig = [(n, x) for n, x, s in areas if abs(x) > 2 * s]
    loop_word = ("loop area beyond 2σ for N = " + ", ".join(
        f"{n} ({'down above up' if x > 0 else 'up above down'})" for n, x in asig) if asig else "loop areas within 2σ")
    big = table[-1]
    psi = big["psi"]
    a, b = psi["jump_at"]
    ia, ib = big["nu_f"].index(a), big["nu_f"].index(b)
    slide = (f"N = {big['n']}: Ψ goes from {_pm(psi['up'][ia], psi['se_up'][ia])} at ν_f = {a:g} to "
             f"{_pm(psi['up'][ib], psi['se_up'][ib])} at {b:g}, where the longest event lasts "
             f"{big['longest_event_up'][ib]:.2f} loading cycles (up) and {big['longest_event_down'][ib]:.2f} (down); "
             f"Ψ loop width {_pm(psi['width'], psi['width_sigma'])} at ν_f = {psi['width_at']:g}")
    from ._study_csn import csn_word, favoured

    words = [csn_word(s.get("csn")) for s in cats]
    wide = [s for s, w in zip(cats, words) if w == "plausible"]
    spans = sum(s["spanning"]["spanning"] for s in cats)
    cl = ("supported" if any(s["spanning"]["spanning"] and s["spanning"]["excess"] > 3 for s in wide)
          else "partly: a power law plausible over ≥ 1 decade (CSN), no excess of spanning events" if wide
          else "not supported at these parameters: the CSN test finds no plausible power law of ≥ 1 decade ("
               + ", ".join(f"{words.count(w)} {w}" for w in dict.fromkeys(words)) + f" of {len(words)})"
               + (", and no system-spanning event occurs" if not spans else ""))
    mfd_cells = "; ".join(f"N = {s['n']}, ν_f = {s['nu_f']}: " + (
        f"CSN α = {s['csn']['alpha']:.2f} ± {s['csn']['alpha_block_err']:.2f} over {s['csn']['decades']:.2f} decades, "
        f"p = {s['csn']['p']:.2f} (B = {s['csn']['bootstrap']}): {w}"
        + (f" (favoured: {', '.join(favoured(s['csn']))})" if favoured(s["csn"]) else "") if s.get("csn") else "no CSN fit")
        + f", {s['spanning']['spanning']} spanning events" for s, w in zip(cats, words))
    bs = "; ".join(f"N = {n}: " + " → ".join(f"{_pm(s['fit']['b'], s['fit']['sigma'], 2)} (ν_f = {s['nu_f']})"
                                            for s in cats if s["n"] == n) for n in sorted({s["n"] for s in cats}))
    row1 = next(r for r in table if r["n"] == 1)
    one = row1["slip_per_block"]
    at = [i for i, x in enumerate(row1["nu_f"]) if abs(x - 0.5) < 1e-9]
    smear = (f"D(1/2) = {one['up'][at[0]]:.3f} and D({row1['nu_f'][at[0] + 1]:g}) = {one['up'][at[0] + 1]:.3f}"
             if at and at[0] + 1 < len(row1["nu_f"]) else "")
    from ._study_transition import transition_evidence

    tr = transition_evidence(data["transition"])
    sak, chain_word = tr["sak"], tr["vas"]
    defined = " ".join(f"{v[0].upper()}{v[1:]}." for v in tr["sentences"].values())
    rows = [
        ("Vasconcelos (1996): the transition stays first order in chains, hysteresis persists up to the "
         "transition, no critical state", f"Lone block: threshold ν_f* = 1/(2√k) confirmed on the engine (offsets of "
         f"the crossing at the smallest ν: {offs}; closing as ν → 0); the 1-block events of the catalogs have the "
         f"closed-form potency to {dev:.1e}. Chain, order parameter D, its transition located and scaled (section "
         f"\"Finite-size scaling of a defined transition\"; N = 1 is the single block, whose first-order jump from "
         f"Δ0 = 0.1507 to 0 at ν_f = 1/2 as ν → 0, docs/physics.md, is smeared at ν = {nu:g}: {smear}): {defined} "
         f"Loop widths of D: {loop_txt} ({len(sig)} of {len(loops)} above 2σ, each biased up by ~1σ); signed loop "
         f"areas Σ(down − up)Δν_f (unbiased): {area_txt}; FSS: {ww}. (The earlier reading, the "
         f"largest change between neighbouring ν_f, sits in a different interval for each N: {jumps}; it follows "
         "no one transition and is not read.)", f"lone block: {lone}. Chain: **{chain_word}**; {loop_word}"),
         ("Carlson & Langer (1989): power-law small events with an excess of large ones", f"{mfd_cells}. "
         f"{notes['cl'][0]}", f"**{notes['cl'][1] or cl}**"
         + (" (ν_f = " + ", ".join(sorted({f"{s['nu_f']:g}" for s in cats})) + "; near ν_f = 1/2 see Mori & Kawamura)"
            if notes["cl"][0] and not notes["cl"][1] else "")
         + f" (ℓ = {cfg['chain']['ell']:g}, ν = {nu:g}"
         + (f" and {cfg['near_half']['nus'][-1]:g}" if notes["cl"][0] else "")
         + "; the `carlson-langer-1991` preset, after J. Xia's reimplementation, has ℓ = 10 and ν = 0.01, and CLST's "
         "drop model is the ν → 0 limit there: presets.py)"),
         ("Mori & Kawamura (2005–08): near-critical behaviour at weak weakening (ν_f ≈ 1/2)", "b from "
         f"ν_f = 0.2 to 0.35: {bs} (Page's slope over a fixed range; the CSN readings of these catalogs: "
         + ", ".join(f"N = {s['n']}, ν_f = {s['nu_f']}: {w}" for s, w in zip(cats, words)) + f", see the table). {slide}. {notes['mk'][0]}",
         (f"**{notes['mk'][1]}** near ν_f = 1/2 (rules: scaling.mfd_reading)" if notes["mk"][1] else
            "**undecided**: broader distributions towards ν_f = 1/2, then, for the longest chain, a switch to "
            "sliding of the whole chain, not a scale-free state; the MFD at ν_f near 1/2 and its finite-size "
            "scaling were not measured")),
         ("Sakaguchi (2002): the transition becomes continuous in long chains", "the transition of D located "
         f"per N and its width W scaled (section \"Finite-size scaling of a defined transition\"): {defined}",
         f"**{sak}**")]
    scan = data.get("ell_scan") or {}
    ells = cfg.get("ell_scan", {}).get("ells", [])
    one_ell = (f"one law, one ℓ (other ℓ only in the ℓ scan: ℓ = {', '.join(f'{e:g}' for e in ells)}, D's transition "
               "located, section \"ℓ scan\")" if scan.get("rows") else "one law, one ℓ")
    caveats = (f"Caveats: {one_ell}; the sweeps of all N at one ν (" + f"{nu:g}"
         + (f"; N ≤ {max(cfg['sweep_small_nu']['sizes'])} also at ν = {cfg['sweep_small_nu']['nu']:g}"
            if data.get("sweeps_small_nu", {}).get("table") else "") + "); errors are seed-to-seed standard errors from "
         + ", ".join(f"{r['seeds']}" for r in table) + " seeds (N = " + ", ".join(str(r["n"]) for r in table)
         + f"); the change of D is measured on a grid of spacing {table[0]['nu_f'][1] - table[0]['nu_f'][0]:.2f} "
         "in ν_f, so a continuous curve also shows a finite change; the loop width is a maximum over noisy "
         "differences (biased up by ~1σ). `workflows/chain-report-large.toml` (same runner; a cluster node or a "
         "free machine) has longer steps, more seeds, ν = 1e-4 and N up to 1024.")
    return [Table(["claim", "evidence here", "verdict"], rows), Paragraph(caveats)]
