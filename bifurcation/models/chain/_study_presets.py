"""The chain report's ``[presets]`` section (issue 17, items 3, 4, 6): one catalog per published
parameter set (presets.py) by the compiled engine through the API, its Clauset–Shalizi–Newman
statistics, and the verdict table, one row per claim, with the rules that turn numbers into words.

The store path (``bifurcation submit``) runs the exact engine only, ~4–7× slower than the compiled one
(docs/chain.md, "Engines"), so 10^6-event catalogs are run here, through ``bifurcation.chain``, by the
report's workflow (``workflows/chain-report.toml``, ``[presets]``). Each catalog is reduced to its
statistics in the worker; the raw catalogs (10^6 events each) are not kept.
"""

from __future__ import annotations

import math
import time

import numpy as np

from ...report.document import Figure, Paragraph, Section, Table
from .clauset import p_reading, p_upper

__all__ = ["PRESET_RULES", "preset_jobs", "preset_section", "verdict_table"]

#: the rules of the verdict words, printed beside the table
PRESET_RULES = (
    "a power law is **ruled out** when the CSN bootstrap p ≤ 0.1 with its one-sided 95 % Clopper–Pearson upper "
    "bound ≤ 0.1 (k of B bootstrap samples; 0 of B bounds p by 1 − 0.05^(1/B): 0.26 for B = 10, 0.095 for B = 30, "
    "0.030 for B = 100, so B < 29 cannot rule a power law out), **plausible** when p > 0.1, "
    "**undecided** otherwise (resolution ±√(p(1 − p)/B)); an alternative is **favoured** when its normalised likelihood ratio is "
    "negative with p < 0.1; an **excess of large events** is ≥ 3× more events with n_blocks ≥ N/2 than the "
    "fitted power law predicts above their smallest potency (with ≥ 5 such events; undecided when x_min lies above "
    "that potency); a **characteristic peak**: ≥ 1 decade above the most populated 0.1-bin of m = log10 P, some "
    "bin exceeds an earlier (smaller-m) bin by more than 3 Poisson σ of the two, i.e. the distribution rises again; "
    "a fit whose tail spans < 1 decade (largest P / x_min < 10) has **no scaling range** and is not read as a "
    "power law; a claim is **not tested** when no run was on its model, and a run on a preset "
    "with numbers NOT READ in the paper (presets.py) **reproduces the preset, not the paper**; b is quoted as "
    "b_P = α − 1 (potency) and b_M = 1.5 (α − 1) (moment magnitude, Hanks–Kanamori), with the moving-block "
    "bootstrap's error")


def preset_jobs(cfg) -> list:
    p = cfg.get("presets")
    if not p:
        return []
    return [(_preset_catalog, (p, dict(run)), run.get("events", 10**5) * 1e-3) for run in p["run"]]


def _preset_catalog(args):
    from .clauset import clauset_fit
    from ...run.progress import event_lines
    from .presets import get_preset
    from .simulate import chain

    p, run = args
    pre = get_preset(run["preset"])
    over = {k: run[k] for k in ("nu", "nu_f", "ell", "n", "sigma", "ends") if k in run}
    par = dict(pre.parameters(), **over)
    c0 = time.process_time()
    r = chain(preset=pre.name, events=int(run["events"]), amplitude=run.get("amplitude", 0.1), seed=run.get("seed", 1),
              engine="compiled", t_max=float(run.get("t_max", 1e4)), verify=float(p.get("verify", 0.0)),
              progress=event_lines(f"study chain: preset {pre.name}"), **over)
    cpu_run = time.process_time() - c0
    t, pot, nb = np.asarray(r.t_start), np.asarray(r.potency), np.asarray(r.n_blocks)
    cycles = par["nu"] * (t - t[0]) if t.size else t
    keep = cycles >= float(p.get("transient_cycles", 1.0))
    out = {"run_cfg": run, "preset": pre.name, "verified_preset": pre.verified, "overrides": over, "parameters": par,
           "why": run.get("why", ""), "claim": run.get("claim", ""), "events": int(t.size), "status": str(r.status),
           "cpu_run": cpu_run, "loading_cycles": float(cycles[-1]) if t.size else 0.0,
           "transient_cycles": float(p.get("transient_cycles", 1.0)), "kept": int(keep.sum())}
    v = r.verification or {}
    out["verify"] = {"checked": v.get("checked", 0), "largest": v.get("largest_any", math.nan),
                     "mismatched": len(v.get("mismatched", []))}
    pot, nb = pot[keep], nb[keep]
    n = int(par["n"])
    out["n_blocks"] = {"max": int(nb.max()) if nb.size else 0, "mean": float(nb.mean()) if nb.size else math.nan,
                       "spanning": int((nb == n).sum()), "large": int((nb >= max(2, n // 2)).sum()),
                       "one": int((nb == 1).sum())}
    distinct = np.unique(pot)
    out["distinct_potencies"] = int(distinct.size)
    out["potency_range"] = [float(pot.min()), float(pot.max())] if pot.size else [math.nan, math.nan]
    #: (max − min)/max: a single block repeats one event, its potencies differing by rounding only
    out["relative_spread"] = float((pot.max() - pot.min()) / pot.max()) if pot.size else math.nan
    m = np.log10(pot[pot > 0])
    edges = np.arange(math.floor(m.min() * 10) / 10, m.max() + 0.2, 0.1) if m.size else np.array([0.0, 0.1])
    counts, _ = np.histogram(m, edges)
    out["mfd"] = {"edges": edges.tolist(), "counts": counts.tolist()}
    c1 = time.process_time()
    if distinct.size < 20 or out["relative_spread"] < 1e-6:
        out["fit"] = None
    else:
        f = clauset_fit(pot, bootstrap=int(run.get("bootstrap", p.get("bootstrap", 10))), block_bootstrap=int(p.get("block_bootstrap", 100)),
                        seed=1, resolution=int(p.get("resolution", 10)))
        out["fit"] = {"n": f.n, "n_tail": f.n_tail, "xmin": f.xmin, "alpha": f.alpha, "alpha_err": f.alpha_err,
                      "alpha_block_err": f.alpha_block_err, "block": f.block, "ks": f.ks, "p": f.p_value,
                      "bootstrap": f.bootstrap, "ratios": {k: list(v) for k, v in f.ratios.items()},
                      "b_P": f.b_potency, "b_M": f.b_magnitude, "words": f.verdict()}
        out["excess"] = _excess(pot, nb, n, f)
    out["cpu_stats"] = time.process_time() - c1
    out["cpu"] = out["cpu_run"] + out["cpu_stats"]
    return out


def _excess(pot, nb, n, f) -> dict:
    """Observed events with n_blocks ≥ N/2 against the power law's count above their smallest potency."""
    large = nb >= max(2, n // 2)
    if not large.any():
        return {"large": 0, "expected": math.nan, "ratio": math.nan}
    p_l = float(pot[large].min())
    obs = int((pot >= p_l).sum())
    exp = f.n_tail * (max(p_l, f.xmin) / f.xmin) ** (1 - f.alpha) if p_l >= f.xmin else math.nan
    return {"large": int(large.sum()), "p_large": p_l, "observed_above": obs, "expected": float(exp),
            "ratio": obs / exp if exp and math.isfinite(exp) and exp > 0 else math.nan}


def _peak(edges, counts) -> dict | None:
    """A rise of the 0.1-bin counts ≥ 1 decade above the most populated bin (PRESET_RULES), or None:
    the highest bin there against the lowest bin before it."""
    c = np.asarray(counts, dtype=float)
    e = np.asarray(edges, dtype=float)[:-1]
    sel = np.nonzero(e >= e[int(np.argmax(c))] + 1.0 - 1e-9)[0]
    best = None
    for i in sel:
        before = [j for j in sel if j < i]
        if not before:
            continue
        j = min(before, key=lambda k: c[k])
        if c[i] - c[j] > 3 * math.sqrt(c[i] + c[j]) and (best is None or c[i] - c[j] > best[2] - best[3]):
            best = (float(e[i]), float(e[j]), c[i], c[j])
    return None if best is None else {"m": best[0], "count": int(best[2]), "m_low": best[1], "low": int(best[3])}


def _scaling_decades(x) -> float:
    f = x.get("fit")
    return math.log10(x["potency_range"][1] / f["xmin"]) if f else math.nan


def _excess_words(ex) -> str:
    if not ex:
        return "–"
    if not ex["large"]:
        return "no event with n_blocks ≥ N/2"
    if not math.isfinite(ex.get("ratio", math.nan)):
        return (f"{ex['large']} events ≥ N/2, smallest P = {ex['p_large']:.3g}, below x_min: no extrapolation "
                "(undecided)")
    return (f"{ex['observed_above']} events with P ≥ {ex['p_large']:.3g} against {ex['expected']:.3g} predicted "
            f"({ex['ratio']:.3g}×)")


def _excess_word(ex) -> str:
    if not ex or not ex.get("large"):
        return "no excess (no event ≥ N/2)"
    if not math.isfinite(ex.get("ratio", math.nan)):
        return "excess undecided (x_min above the large events)"
    return "**excess**" if ex["large"] >= 5 and ex["ratio"] >= 3 else "no excess"


def _fit_word(x) -> str:
    f = x.get("fit")
    if f is None:
        return "no fit"
    if _scaling_decades(x) < 1:
        return "no scaling range"
    return "power law " + p_reading(f["p"], f["bootstrap"])


def _par(x) -> str:
    p = x["parameters"]
    return (f"N = {p['n']}, ℓ = {p['ell']:g}, ν = {p['nu']:g}, ν_f = {p['nu_f']:g} (α = {0.5 / p['nu_f']:g}), "
            f"σ = {p['sigma']:g}, {p['ends']}")


def _fit_cell(x) -> str:
    f = x.get("fit")
    if f is None:
        return (f"one size: P = {x['potency_range'][1]:.10g}, every event within {x['relative_spread']:.1e} of it "
                "(rounding): no size distribution to fit")
    lr = ", ".join(f"{k.replace('_', ' ')} R = {r:+.1f} (p = {p:.2g})" for k, (r, p) in f["ratios"].items())
    res = math.sqrt(max(f["p"] * (1 - f["p"]), 1 / f["bootstrap"]) / f["bootstrap"]) if f["bootstrap"] else math.nan
    dec = _scaling_decades(x)
    return ((f"**no scaling range** ({dec:.2f} decades above x_min): " if dec < 1 else "")
            + f"α = {f['alpha']:.3f} ± {f['alpha_block_err']:.3f} (block bootstrap, blocks of {f['block']}; i.i.d. "
            f"{f['alpha_err']:.3f}) above x_min = {f['xmin']:.3g} ({f['n_tail']} of {f['n']} events); b_P = "
            f"{f['b_P']:.3f}, b_M = {f['b_M']:.3f}; KS (powerlaw's D) {f['ks']:.4f}, two-sided ≤ "
            f"{math.ceil((f['ks'] + 1 / f['n_tail']) * 1e4) / 1e4:.4f}; p = {f['p']:.2f} ± {res:.2f} "
            f"({round(f['p'] * f['bootstrap'])} of {f['bootstrap']} samples, ≤ {p_upper(f['p'], f['bootstrap']):.2g} at "
            f"95 %); LR: {lr}")


def _events(x) -> str:
    """What a catalog of the ν-lowered runs holds: its events and their definition."""
    return (f"{x['kept']} of {x['events']} events kept after {x['transient_cycles']:g} loading cycle(s); an event "
            "lasts until every block is stuck again")


def preset_section(data) -> list:
    runs = data.get("presets") or []
    if not runs:
        return []
    Bs = sorted({int(x["fit"]["bootstrap"]) for x in runs if x.get("fit")}) or [
        int(data.get("presets_cfg", {}).get("bootstrap", 10))]
    intro = ("One catalog per row, compiled engine (`bifurcation.chain(preset=..., engine=\"compiled\")`, "
         "docs/chain.md \"Engines\") from the seeded random start (amplitude 0.1, seed 1); events of the first "
         f"{runs[0]['transient_cycles']:g} loading cycle(s) dropped. Sizes are potencies P; the fits are "
         "Clauset–Shalizi–Newman's through `powerlaw` (`clauset.clauset_fit`, x_min searched over "
         f"{data.get('presets_cfg', {}).get('resolution', 10)} data values per decade; "
         f"B = {' or '.join(map(str, Bs))} bootstrap samples for p (per run: the CSN fit column), chosen to fit the "
         "CPU budget (each is an x_min search over ~10^6 events, 3–10 CPU s here): p is resolved to about "
         + " or ".join(f"±{math.sqrt(0.25 / b):.2f}" for b in Bs) + " at p = 0.5, and 0 of B samples bounds p by "
         "1 − 0.05^(1/B) at 95 % (Clopper–Pearson): "
         + "; ".join(f"{p_upper(0.0, b):.3f} for B = {b}, " + ("enough to rule a power law out when no sample is as "
                     "far from its fit as the data" if p_upper(0.0, b) <= 0.1 else "not enough to rule a power law out")
                     for b in Bs) + "; "
         + f"moving-block bootstrap of α with {data.get('presets_cfg', {}).get('block_bootstrap', 100)} "
         "resamples of blocks of ⌈n^(1/3)⌉ events). "
         "KS (powerlaw's D): `powerlaw`'s KS distance, whose empirical CDF is (i − 1)/n at the i-th smallest size, "
         "one side of each step (powerlaw-devs/powerlaw issue #111); the two-sided supremum lies between D and "
         "D + 1/n_tail (the bound given), and is not given itself because these catalogs are not kept; the bootstrap p "
         "compares like with like. Where a preset's own number was changed, the row says why. "
         "Which numbers of each preset were read in a source: docs/chain.md \"Presets\" and presets.py. "
         "Event membership: all-stuck, so the chain presets are run here at a smaller ν than their own 0.01 (the "
         "rows say why); at their own ν the events are split in time by a velocity threshold instead "
         "(`subevent_study.py`, [PUBLISHED_NU.md](PUBLISHED_NU.md), the verdict table's fourth column). "
         + f"This section: {sum(x['cpu'] for x in runs):.0f} CPU s in all (each run's own CPU time, on a 2-core "
         "machine shared with other jobs; `--presets-only`). "
         + "The catalogs are chaotic event sequences: which event comes when, and so every digit of an individual "
         "event, depends on the CPU's rounding and instruction set (numba and heyoka compile for the host CPU); the counts, α, b, p and the ratios "
         "move with the CPU within their errors only, and the verify column (the compiled engine against the "
         "exact one from the same state) is a rounding-level figure whose digits depend on the CPU.")
    rows = []
    for x in runs:
        nb, v = x["n_blocks"], x["verify"]
        ex = x.get("excess") or {}
        exc = _excess_words(ex)
        pk = _peak(x["mfd"]["edges"], x["mfd"]["counts"]) if x.get("fit") else None
        peak = "–" if x.get("fit") is None else ("none" if not pk else f"m = {pk['m']:.1f}: {pk['count']} events "
                                                 f"against {pk['low']} at m = {pk['m_low']:.1f}")
        rows.append([f"`{x['preset']}` ({_par(x)}){'; ' + x['why'] if x['why'] else ''}",
                     f"{x['events']} ({x['kept']}), {x['status']}", f"{x['loading_cycles']:.2f}",
                     f"{x['cpu_run']:.0f} + {x['cpu_stats']:.0f}",
                     f"{v['checked']}, {v['largest']:.1e}{', ' + str(v['mismatched']) + ' differ in size' if v['mismatched'] else ''}",
                     f"{nb['mean']:.2f} / {nb['max']}, {nb['spanning']}, {nb['large']}", _fit_cell(x), exc, peak])
    return [Section("Published parameter sets (presets): catalogs of 10^6 events", [
        Paragraph(intro),
        Table(["preset (run as)", "events (kept)", "loading cycles", "CPU s (run + stats)",
               "verify: events re-run by the exact engine, largest difference",
               "sizes: mean / max n_blocks, spanning, ≥ N/2", "CSN fit", "large-event excess", "peak"], rows),
        Figure("fig_presets.png", "Events per 0.1 in m = log10 P of each fitted preset catalog (steps; the "
               "single block's one-size catalog has no fit and is not drawn). The short bar high at the left of "
               "each curve is its smallest bin (0.1 wide in m): nearly all the 1-block events fall in it. "
               "Dotted: the CSN power law above its x_min as a density per 0.1 in m, "
               "n_tail (α − 1) ln 10 · 0.1 (P/x_min)^(1 − α).",
               alt="magnitude-frequency of the preset catalogs")])]


#: the rule of the published-ν column (events split by V_th, subevent_study.py)
PUBLISHED_NU_RULE = (
    "at the preset's own ν the events are split in time by V_th (an event lasts while some block is faster than "
    "V_th); events that last ≥ 1 loading cycle are **slides of ≥ 1 loading cycle** (the chain slides for "
    "cycles: not stick-slip events), and a size distribution that holds them is read with that said; "
    "fits and words otherwise by the rules above")


def _pub_cell(x) -> str:
    """One published-ν catalog (subevent_study.run_preset's record) in a verdict-table cell."""
    f, nb, du = x["fit"], x["n_blocks"], x["duration"]
    lr = ", ".join(f"{k.replace('_', ' ')} R = {v[0]:+.1f} (p = {v[1]:.2g})" for k, v in f["ratios"].items())
    res = math.sqrt(max(f["p"] * (1 - f["p"]), 1 / f["bootstrap"]) / f["bootstrap"]) if f["bootstrap"] else math.nan
    dec = math.log10(f["largest"] / f["xmin"])
    word = "no scaling range" if dec < 1 else "power law " + p_reading(f["p"], f["bootstrap"])
    slides = du["over_one_cycle"]
    ex = x["excess"]
    exw = ("excess undecided (x_min above the large events)" if ex["large"] and "expected" not in ex else
           "no event ≥ N/2" if not ex["large"] else
           ("**excess**" if ex["large"] >= 5 and ex["observed"] >= 3 * ex["expected"] else "no excess")
           + f" ({ex['observed']} with P ≥ {ex['p_large']:.3g} against {ex['expected']:.3g})")
    k = round(f["p"] * f["bootstrap"])
    return (f"α = {0.5 / x['nu_f']:g} (`{x['preset']}`, N = {x['n']}, ℓ = {x['ell']:g}, ν = {x['nu']:g}, σ = "
            f"{x['sigma']:g}, {x['ends']}; an event lasts while some block is faster than V_th = {x['v_threshold']:g}): "
            f"{x['kept']} events kept "
            f"({x['status']}; {x['loading_cycles']:.0f} loading cycles, {x['cpu_per_event'] * 1e3:.3g} CPU ms per "
            f"event: 10^6 events would take {x['cpu_per_event'] * 1e6 / 3600:.0f} CPU h); n_blocks mean {nb['mean']:.2f}, {nb['large']} ≥ N/2; {slides} events last ≥ 1 loading cycle"
            f"{' (**slides of ≥ 1 loading cycle**)' if slides else ''}; {word}: α = {f['alpha']:.3f} ± {f['alpha_block_err']:.3f} "
            f"above x_min = {f['xmin']:.3g} ({f['n_tail']} events, {dec:.2f} decades), b_P = {f['b_P']:.3f}, "
            f"b_M = {f['b_M']:.3f}, p = {f['p']:.2f} ± {res:.2f} ({k} of B = {f['bootstrap']}, ≤ "
            f"{p_upper(f['p'], f['bootstrap']):.2g} at 95 %); LR: {lr}; {exw}")


def verdict_table(cfg, data, old_rows: dict) -> list:
    """One row per claim (issue 17, item 6), each on its own model where a run was on it."""
    runs = {(x["preset"], x["parameters"]["nu_f"]): x for x in (data.get("presets") or [])}

    def find(name):
        return [x for (n, _), x in runs.items() if n == name]

    rows = []
    vas = find("vasconcelos-1996")
    v_ev = (f"`vasconcelos-1996` (N = 1, σ = 0, ν = 1e-9, ν_f = 1/2; {vas[0]['kept']} of {vas[0]['events']} events kept, "
            f"an event lasts until the block sticks again): {vas[0]['kept']} events of one potency "
            f"{vas[0]['potency_range'][1]:.10g} (spread {vas[0]['relative_spread']:.1e}): the single block repeats "
            "one event (its Δ at ν = 1e-9, which approaches the ν → 0 value 0.1507 only logarithmically at "
            "ν_f = 1/2, docs/physics.md \"Asymptotics at small ν\"); chains are discussed, not run, in the paper. "
            if vas else "")
    rows.append(("Vasconcelos, PRL 76, 4865 (1996): single block first order at ν_f = 1/2; chains not critical",
                 v_ev + "The σ = 0 chains of this report (its Carlson–Langer friction, ℓ = 1, free ends, N = 1–256 at "
                 "ν = 1e-3 and N ≤ 16 at 1e-4, events until all blocks are stuck) are read in the next section: " + old_rows.get("vas", "–"),
                 "single block: **confirmed** (docs/physics.md: Δ0 falls from 0.1507 to 0 at ν_f = 1/2 as ν → 0; "
                 "the catalog adds only that every event is the same); chains: "
                 + old_rows.get("vas_word", "**undecided**") + " (ℓ and ν of chains are not in the paper)"))
    cl = find("carlson-langer-1991")
    cl_beside = "no run on the preset"
    if cl:
        x = cl[0]
        f = x.get("fit")
        ex = x.get("excess") or {}
        pk = _peak(x["mfd"]["edges"], x["mfd"]["counts"]) if f else None
        exc = _excess_words(ex) + ("; rise at m = " + format(pk["m"], ".1f") if pk else "; no rise")
        word = (_fit_word(x) + (f" (b_P = {f['b_P']:.2f}, b_M = {f['b_M']:.2f})" if f else "")
                + "; large events: " + _excess_word(ex) + ("; characteristic peak" if pk else ""))
        rows.append(("Carlson & Langer (PRL 62, 2632; PRA 40, 6470 (1989)) / CLST (PRA 44, 884 (1991)): power-law "
                     "small events plus an excess of large ones",
                     f"`carlson-langer-1991` ({_par(x)}; {_events(x)}): {_fit_cell(x)}; {exc}",
                     f"{word} — on the preset, which reproduces J. Xia's reimplementation (ℓ, α, ν) with σ, N, "
                     "ends NOT READ and ν lowered to approach CLST's ν → 0 limit: **not a test of the paper** until "
                     "those are read"))
        cl_beside = ("large events beyond the power law: ours " + _excess_word(ex) + f" ({_excess_words(ex)})"
                     + (f" and a rise at m = {pk['m']:.1f}" if pk else ", no rise")
                     + " — the kind of finding the texts read state; small events: ours " + _fit_word(x)
                     + (f" (b_P = {f['b_P']:.2f})" if f else "")
                     + " by CSN, where the texts read give no exponent and no test of 'consistent with'"
                     " (on the preset, not CLST's parameters)")
    else:
        rows.append(("Carlson & Langer 1989 / CLST 1991", "no run", "**not tested**"))
    rows.append(("de Sousa Vieira, Vasconcelos & Nagel, PRE 47, R2221 (1993)",
                 "the paper could not be read (not found by search); no model or parameters to run", "**not tested**"))
    mk = sorted(find("mori-kawamura-2006"), key=lambda x: -x["parameters"]["nu_f"])
    if mk:
        cells = []
        for x in mk:
            f, ex = x.get("fit"), x.get("excess") or {}
            pk = _peak(x["mfd"]["edges"], x["mfd"]["counts"]) if f else None
            cells.append(f"α = {0.5 / x['parameters']['nu_f']:g} ({_events(x)}): " + (
                f"{_fit_word(x)}, b_P = {f['b_P']:.3f} ± {f['alpha_block_err']:.3f} (b_M = {f['b_M']:.2f}) above "
                f"x_min = {f['xmin']:.3g} ({f['n_tail']} events, {_scaling_decades(x):.2f} decades), p = {f['p']:.2f} "
                f"({round(f['p'] * f['bootstrap'])} of {f['bootstrap']}, ≤ {p_upper(f['p'], f['bootstrap']):.2g} at 95 %); "
                + (f"**characteristic peak** at m = {pk['m']:.1f} ({pk['count']} against {pk['low']} at "
                   f"m = {pk['m_low']:.1f})" if pk else "no characteristic peak")
                + f"; {_excess_word(ex)}" if f else "no fit"))
        rows.append(("Mori & Kawamura, PRL 94, 058501 (2005); JGR 111, B07302 (2006): GR-like at α = 1, "
                     "characteristic peak at α ≥ 2",
                     f"`mori-kawamura-2006` (N = {mk[0]['parameters']['n']}, ℓ = {mk[0]['parameters']['ell']:g}, "
                     f"ν = {mk[0]['parameters']['nu']:g}, σ = {mk[0]['parameters']['sigma']:g}, "
                     f"{mk[0]['parameters']['ends']}): " + "; ".join(cells),
                     "**not tested**: every number of the preset is the issue's summary, none read in MK; the "
                     "numbers beside reproduce that summary (words by the rules below) only"))
    else:
        rows.append(("Mori & Kawamura 2005/2006", "no run", "**not tested**"))
    rows.append(("Sakaguchi, arXiv nlin/0210057: the stick-slip transition turns continuous in long chains",
                 "its model has friction with a state variable (its abstract); the chains here have velocity-only "
                 "friction. On the σ = 0 Carlson–Langer chains: " + old_rows.get("sak", "–"),
                 "**not tested** on its model"))
    pub = data.get("published_nu") or []

    def pub_cells(name):
        xs = sorted((x for x in pub if x["preset"] == name), key=lambda x: -x["nu_f"])
        return "; ".join(_pub_cell(x) for x in xs) if xs else "not run"

    keys = ["vasconcelos-1996", "carlson-langer-1991", None, "mori-kawamura-2006", None]
    beside = {"vas": "Δ0(ν_f = 1/2) of the Carlson–Langer block as ν → 0: ours 0.1507294408752 (docs/physics.md, "
                     "\"Asymptotics at small ν\": the approach is logarithmic, which a power-law extrapolation misses), "
                     "the paper's 0.17",
              "cl": cl_beside,
              "dsvvn": "not compared: its chain's N, ℓ, ν and friction were not read, and its loading–unloading "
                       "hysteresis is not the ν_f-sweep loop measured here (section \"Order parameter and hysteresis\")",
              "mk": "not compared: the first two are MK's two-dimensional models; for the 1D chain only the third, "
                    "MK's own clause on their 1D models (near-critical behaviour only by fine-tuning the parameters, "
                    "which parameters and values not said), was read — the first column's claim (GR-like at α = 1, a "
                    "peak at α ≥ 2) is issue 17's summary of MK, not MK's text (the stored opening of MK 2005 speaks "
                    "of CL's dependence on the friction parameter: row above)",
              "sak": "not compared: its friction has a state variable; no exponent is in the abstract"}
    lit = [_literature_cell(c, beside[c]) for c in ("vas", "cl", "dsvvn", "mk", "sak")]
    rows = [(r[0], r[1], (pub_cells(k) if k and k != "vasconcelos-1996" else
                          "– (N = 1: its own ν, above)" if k else "not run"), li, r[2])
            for r, k, li in zip(rows, keys, lit)]
    size = []
    if pub:
        cost = [x["cpu_per_event"] for x in pub]
        size = [Paragraph(
            f"Catalog sizes at the presets' own ν: {min(x['kept'] for x in pub)}–{max(x['kept'] for x in pub)} events "
            f"per catalog, each cut by its CPU budget ({', '.join(sorted({x['status'] for x in pub}))}). The compiled "
            "engine runs these chains with σ > 0 (`bifurcation.chain(..., engine=\"compiled\")`, all-stuck events) "
            "and splits events by V_th in its own loop (`_subevents.py`, through `subevent_study.py`; "
            "`bifurcation.chain` takes `v_threshold` with the exact engine only). Its measured cost per event at the "
            f"presets' N and ν = 0.01 is {min(cost) * 1e3:.3g}–{max(cost) * 1e3:.3g} CPU ms (a chain-wide slide "
            "of hundreds of blocks is one event), so 10^6 events per catalog would take "
            f"{min(cost) * 1e6 / 3600:.0f}–{max(cost) * 1e6 / 3600:.0f} CPU hours each, and even 10^4 events "
            f"{min(cost) * 1e4 / 3600:.1f}–{max(cost) * 1e4 / 3600:.1f} CPU hours: the readings at the presets' own ν "
            f"rest on {min(x['kept'] for x in pub)}–{max(x['kept'] for x in pub)} events "
            f"({sum(math.log10(x['fit']['largest'] / x['fit']['xmin']) < 1 for x in pub)} of {len(pub)} fits with "
            "**no scaling range**).")]
    return [Section("Verdict table (issue 17): one row per claim, each on its own model", [
        Table(["claim", "run and numbers (ν lowered, all-stuck events)",
               "at the preset's own ν (events split by V_th; PUBLISHED_NU.md)",
               "published finding read (source, place, its words) and ours beside it", "verdict"], rows), *size,
        Paragraph("Rules: " + PRESET_RULES + "; " + PUBLISHED_NU_RULE + ". Published numbers beside ours: the only "
          "number read in these papers is Vasconcelos' Δ = 0.17 (first row); for the chains, the texts that could "
          "be read (stored openings: abstracts and introductions, bifurcation/models/chain/literature.py) state "
          "findings in words only — no exponent, no b, no parameter of CL, CLST, MK or de Sousa Vieira–"
          "Vasconcelos–Nagel — so the fourth column sets words beside words; a paper's account of another paper "
          "is marked secondary; the searches that found nothing are listed in docs/chain.md, \"Presets\".")])]


def _literature_cell(claim: str, beside: str) -> str:
    """The fourth column: every finding read for ``claim`` (literature.py), then ours beside it."""
    from .literature import findings_for

    fs = findings_for(claim)
    read = " ".join(f"{f.source}, {f.place}{' (secondary: its account of another paper)' if f.secondary else ''}: "
                    f"“{f.quote}”" for f in fs) if fs else "none read (docs/chain.md, \"Presets\": what was searched)"
    return read + (f" — beside ours: {beside}" if beside else "")


def presets_figure(out, runs) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for x in runs:
        if x.get("fit") is None:
            continue
        e, c = np.array(x["mfd"]["edges"]), np.array(x["mfd"]["counts"], dtype=float)
        ax.step(e[:-1], np.where(c > 0, c, np.nan), where="post",
                label=f"{x['preset']} α = {0.5 / x['parameters']['nu_f']:g}")
        f = x["fit"]
        m = np.linspace(math.log10(f["xmin"]), e[-1], 50)
        # the fitted density per 0.1 bin of m: n_tail (α − 1) ln10 0.1 (P/x_min)^(1 − α)
        ax.plot(m, f["n_tail"] * (f["alpha"] - 1) * math.log(10) * 0.1 * (10**m / f["xmin"]) ** (1 - f["alpha"]),
                "k:", lw=0.8)
    ax.set_yscale("log")
    ax.set_xlabel("m = log10 P")
    ax.set_ylabel("events per 0.1 in m")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "fig_presets.png", dpi=110, metadata={"Software": None})
    plt.close(fig)
