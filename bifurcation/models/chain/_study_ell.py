"""The chain report's ℓ scan (issue 17, item 5): the transition of the order parameter D located per (ℓ, N)
and scaled in N for ℓ = 1, 3, 10, and a sequence at fixed N/ℓ toward the continuum limit (ℓ → ∞).

The workflow's ``[ell_scan]`` table. Per (ℓ, N, seed) one ``analysis.sweep_nu_f`` run (ν_f up, then down,
within one run) on a grid in units of the lone-block threshold ν_f*(ℓ) = 1/(2√(1 + 2ℓ²)) (docs/chain.md),
so that every ℓ is resolved alike around its own ν_f* (0.289, 0.115, 0.035 for ℓ = 1, 3, 10). The random
start's amplitude is ``amplitude / ℓ²``: the spring stresses of a start u_j = A r_j are ~ℓ²A, and a start
stress spread far above the threshold takes that many loading cycles to forget (measured, ℓ = 10, N = 16,
ν = 1e-3: from A = 0.1 the spread 30.6 shrinks by ~1.5 per loading cycle, and D reaches the statistics of a
start from A = 0.001 only after 10–14 cycles; docs/chain.md, "ℓ scan"). D is left out (NaN) at steps where
some seed's event lasted longer than ``longest_event`` loading cycles (merged slides, as in ``[sweep]``).
Each finished run is kept at once in ``ell_scan.json`` (beside data.json): a stopped
``--ell-scan-only`` resumes with the runs still missing. The location is crossing.py's (ν_½ with its
bootstrap and grid errors, ν_χ), in units of ν_f* and then of ν_f; the N-dependence per ℓ by
crossing.location_fit (ν_∞ + a/N) and its words (crossing.location_words: ν_f* or 1/2).
"""

from __future__ import annotations

import json
import math
import os
import time
from pathlib import Path

import numpy as np

from ...report.document import Figure, Paragraph, Section, Table

__all__ = ["ELL_FILE", "ell_scan_figure", "ell_scan_jobs", "ell_scan_section", "ell_scan_stats", "load_runs",
           "missing_jobs", "pairs", "record_run", "settings"]

#: the scan's runs, one entry per (ℓ, N, seed), written after each run (the checkpoint)
ELL_FILE = "ell_scan.json"
SAMPLES, SEED = 2000, 1


def star(ell: float) -> float:
    """The lone-block threshold ν_f* = 1/(2√(1 + 2ℓ²)) of an interior block (docs/chain.md)."""
    return 0.5 / math.sqrt(1 + 2 * ell**2)


#: the [ell_scan] keys that choose which runs are made, not how each is run: a kept run stays valid when they change
_SELECTION = ("ells", "sizes", "seeds", "continuum")


def settings(cfg) -> dict:
    """What a kept run must have been run with: [ell_scan] but its selection keys, and [chain]'s law, ν, ends."""
    c = cfg["chain"]
    return {"law": c["law"], "nu": float(c["nu"]), "ends": c["ends"],
            **{k: v for k, v in cfg["ell_scan"].items() if k not in _SELECTION}}


def pairs(cfg) -> list[tuple[float, int]]:
    """(ℓ, N) of the scan: every ℓ × every size, then the fixed-N/ℓ sequences (N = round(ratio · ℓ)),
    each pair once, in that order."""
    s = cfg["ell_scan"]
    out = [(float(ell), int(n)) for ell in s["ells"] for n in s["sizes"]]
    for ratio in s.get("continuum", []):
        out += [(float(ell), int(round(ratio * ell))) for ell in s["ells"]]
    return list(dict.fromkeys(out))


def _key(ell: float, n: int, seed: int) -> str:
    return f"{ell:g}/{n}/{seed}"


def ell_scan_jobs(cfg) -> list:
    """(function, args, weight) of every run of the scan (weight: N ℓ, the longest first)."""
    s = cfg.get("ell_scan")
    if not s:
        return []
    st = settings(cfg)
    return [(_ell_sweep, (st, ell, n, seed), n * max(ell, 1.0) * 1e-2)
            for ell, n in pairs(cfg) for seed in range(1, s["seeds"] + 1)]


def _ell_sweep(args) -> dict:
    from .analysis import sweep_nu_f

    st, ell, n, seed = args
    grid = [r * star(ell) for r in st["ratios"]]
    c0 = time.process_time()
    out = sweep_nu_f(st["law"], n=n, ell=ell, nu=st["nu"], nu_f_values=grid + grid[::-1],
                     cycles_per_step=st["cycles_per_step"], max_events_per_step=st["max_events_per_step"],
                     transient_cycles=st["transient_cycles"], ends=st["ends"], amplitude=st["amplitude"] / ell**2,
                     seed=seed)
    keep = ("slip_per_block", "longest_event", "events", "cycles", "slip_fraction", "status")
    return {"ell": ell, "n": n, "seed": seed, "cpu": time.process_time() - c0, **{k: out[k] for k in keep}}


def load_runs(out: Path, cfg) -> dict:
    """The kept runs of ``out/ell_scan.json`` by key, if they were run with this workflow's settings."""
    path = Path(out) / ELL_FILE
    if not path.is_file():
        return {}
    doc = json.loads(path.read_text())
    if doc.get("settings") != json.loads(json.dumps(settings(cfg))):
        return {}
    return {_key(r["ell"], r["n"], r["seed"]): r for r in doc.get("runs", [])}


def missing_jobs(out: Path, cfg) -> list:
    done = load_runs(out, cfg)
    return [j for j in ell_scan_jobs(cfg) if _key(*j[1][1:]) not in done]


def record_run(out: Path, cfg, run: dict, fresh: bool = False) -> None:
    """Add ``run`` to ``out/ell_scan.json`` (written beside and renamed into place: a kill leaves the earlier
    file whole); ``fresh``: drop the runs kept so far."""
    runs = {} if fresh else load_runs(out, cfg)
    runs[_key(run["ell"], run["n"], run["seed"])] = run
    text = json.dumps({"settings": settings(cfg), "runs": sorted(runs.values(), key=lambda r: (r["ell"], r["n"], r["seed"]))},
                      indent=1, default=float)
    tmp = Path(out) / f".{ELL_FILE}.part-{os.getpid()}"
    try:
        tmp.write_text(text)
        os.replace(tmp, Path(out) / ELL_FILE)
    finally:
        tmp.unlink(missing_ok=True)


def ell_scan_stats(out: Path, cfg) -> dict | None:
    """Per (ℓ, N): D over seeds on both branches, the located transition (crossing.locate on the up branch, in
    units of ν_f*), the FSS fit per ℓ and the fixed-N/ℓ sequences; None without a complete scan."""
    from .crossing import locate, location_fit, location_words

    s = cfg.get("ell_scan")
    if not s:
        return None
    runs = load_runs(out, cfg)
    ratios = np.asarray(s["ratios"], dtype=float)
    k = ratios.size
    rows = []
    for ell, n in pairs(cfg):
        rs = [runs.get(_key(ell, n, seed)) for seed in range(1, s["seeds"] + 1)]
        if any(r is None for r in rs):
            continue
        d = np.array([r["slip_per_block"] for r in rs], dtype=float)
        longest = np.max([r["longest_event"] for r in rs], axis=0)
        merged = longest > s.get("longest_event", 0.5)
        d[:, merged] = np.nan
        up, down = d[:, :k], d[:, k:][:, ::-1]
        m = len(rs)
        se = (lambda a: a.std(axis=0, ddof=1) / math.sqrt(m)) if m > 1 else (lambda a: 0 * a[0])
        loc = locate(ratios, up.mean(0), se(up), samples=SAMPLES, seed=SEED)
        rows.append({"ell": ell, "n": n, "seeds": m, "star": star(ell), "d_up": up.mean(0).tolist(),
                     "se_up": se(up).tolist(), "d_down": down.mean(0).tolist(), "se_down": se(down).tolist(),
                     "merged_up": merged[:k].tolist(), "merged_down": merged[k:][::-1].tolist(),
                     "half": loc["half"], "peak": loc["peak"], "width": loc["width"], "drop": loc["drop"],
                     "events": int(sum(sum(r["events"]) for r in rs)), "cpu": float(sum(r["cpu"] for r in rs))})
    fits = {}
    nu = float(cfg["chain"]["nu"])
    for ell in s["ells"]:
        ch = [r for r in rows if r["ell"] == ell and r["n"] in s["sizes"] and r["n"] > 1]
        f = location_fit([r["n"] for r in ch], [r["half"]["value"] * r["star"] for r in ch],
                         [r["half"]["sigma"] * r["star"] for r in ch])
        fits[f"{ell:g}"] = {"fit": f, "words": location_words(f, star(ell)), "lone": lone_half(cfg["chain"]["law"], ell, nu, ratios)}
    return {"rows": rows, "fits": fits, "ratios": ratios.tolist(), "runs": len(runs),
            "planned": len(ell_scan_jobs(cfg)), "cpu": float(sum(r["cpu"] for r in runs.values())),
            "events": int(sum(sum(r["events"]) for r in runs.values()))}


def lone_half(law: str, ell: float, nu: float, ratios) -> tuple[float, float, float]:
    """(ν_½/ν_f*, ν_χ/ν_f*, k·P at the smallest ratio) of the lone interior block among stuck neighbours at this
    ν, on the same grid and by the same locators: its k·P is the single block's Δ(ν/√k, √k ν_f) with √k ν_f = ratio/2 (docs/chain.md,
    "Lone-block threshold"), so the reference for a chain transition that only follows the lone block."""
    import bifurcation as bf

    from .crossing import half_crossing, slope_peak

    k = 1 + 2 * ell**2
    d = [float(bf.slip(law, nu=nu / math.sqrt(k), nu_f=r / 2).delta) for r in ratios]
    return half_crossing(ratios, d)[0], slope_peak(ratios, d)[0], d[0]


def _pm(q: dict, scale: float = 1.0, d: int = 3) -> str:
    v, s = q["value"], q["sigma"]
    if not math.isfinite(v):
        return f"– ({q.get('status', 'not located')})"
    pct = f" ({100 * q['found']:.0f} %)" if q.get("found", 1) < 0.995 else ""
    return f"{v * scale:.{d}f} ± {s * scale:.{d}f}{pct}" if math.isfinite(s) else f"{v * scale:.{d}f}{pct}"


def _title(cfg) -> str:
    return f"ℓ scan ({', '.join(f'{e:g}' for e in cfg['ell_scan']['ells'])}) and the continuum limit"


def ell_scan_section(cfg, st: dict) -> list:
    s = cfg["ell_scan"]
    nu = float(cfg["chain"]["nu"])
    grid = ", ".join(f"{r:g}" for r in s["ratios"])
    if not st["rows"]:
        return [Section(_title(cfg), [Paragraph(
            f"`[ell_scan]` planned {st['planned']} runs; {st['runs']} are in {ELL_FILE}: none of its (ℓ, N) complete. "
            "Run `bifurcation study chain WORKFLOW --ell-scan-only --out DIR` (it resumes).")], level=3)]
    rows = []
    for r in st["rows"]:
        left = [f"{x:g}" for x, m in zip(st["ratios"], r["merged_up"]) if m]
        rows.append([f"{r['ell']:g}", f"{r['n']}", f"{r['n'] / r['ell']:g}", f"{r['star']:.4f}", f"{r['seeds']}",
                     _pm(r["half"]), _pm(r["half"], r["star"], 4), _pm(r["peak"]), _pm(r["width"], 1, 2),
                     f"{r['d_up'][0]:.3f} → {np.nanmin(r['d_up']):.4f}", ", ".join(left) or "none",
                     f"{r['cpu']:.0f}"])
    fit_rows = []
    for ell in s["ells"]:
        f = st["fits"][f"{ell:g}"]
        v, w = f["words"]
        ft = f["fit"]
        ratio = (f"{ft['nu_inf'] / star(ell):.3f} ± {ft['nu_inf_sigma'] / star(ell):.3f}"
                 if math.isfinite(ft["nu_inf"]) else "–")
        lone, lone_peak, _ = f["lone"]
        beside = (f"{lone:.3f} ({(ft['nu_inf'] / star(ell) - lone) / (ft['nu_inf_sigma'] / star(ell)):+.1f}σ)"
                  if math.isfinite(lone) and math.isfinite(ft["nu_inf"]) and ft["nu_inf_sigma"] > 0 else f"{lone:.3f}")
        beside += f"; ν_χ/ν_f* {lone_peak:.3f}"
        fit_rows.append([f"{ell:g}", f"{star(ell):.4f}", ratio, beside, f"**{v}**: {w}"])
    cont = []
    for c in s.get("continuum", []):
        seq = [r for ell in s["ells"] for r in st["rows"] if r["ell"] == ell and r["n"] == int(round(c * ell))]
        for a, b in zip(seq, seq[1:]):
            va, vb = a["half"]["value"], b["half"]["value"]
            sig = math.hypot(a["half"]["sigma"], b["half"]["sigma"])
            if math.isfinite(va) and math.isfinite(vb) and sig > 0:
                cont.append(f"N/ℓ = {c:g}: ν_½/ν_f* {va:.3f} (ℓ = {a['ell']:g}, N = {a['n']}) → {vb:.3f} "
                            f"(ℓ = {b['ell']:g}, N = {b['n']}): {(vb - va) / sig:+.1f}σ")
    spacing = st["ratios"][1] - st["ratios"][0]
    step = [f"ℓ = {r['ell']:g}, N = {r['n']}" for r in st["rows"]
            if math.isfinite(r["width"]["value"]) and r["width"]["value"] - 2 * r["width"]["sigma"] <= spacing]
    steps = (f" The change is **step-like on this grid** (W − 2σ ≤ the spacing {spacing:g} ν_f*: the grid cannot tell it "
             f"from a jump) at {'; '.join(step)}; elsewhere it is resolved as a smooth fall." if step else
             f" No (ℓ, N) has W − 2σ ≤ the spacing {spacing:g} ν_f*: every change is resolved as a smooth fall.")
    located = [r for r in st["rows"] if math.isfinite(r["half"]["value"])]
    span = ""
    if located:
        lo = min(r["half"]["value"] for r in located)
        hi = max(r["half"]["value"] for r in located)
        below = all(r["half"]["value"] + 2 * r["half"]["sigma"] < 0.5 / r["star"] for r in located)
        span = (f". Over the scan the located ν_½ lie between {lo:.2f} and {hi:.2f} ν_f*(ℓ) ({len(located)} of "
                f"{len(st['rows'])} (ℓ, N))" + ("; each (+2σ) lies below the uniform mode's 1/2 in its own ℓ's units "
                "(1/2 = " + ", ".join(f"{0.5 / star(e):.2f} ν_f* at ℓ = {e:g}" for e in s["ells"]) + ")" if below else ""))
    return [Section(_title(cfg), [
        Paragraph(
            f"`[ell_scan]` (run by `bifurcation study chain WORKFLOW --ell-scan-only`; its runs kept in {ELL_FILE}, "
            f"one per (ℓ, N, seed), so a stopped scan resumes): the sweep of D above (ν_f up, then down, within one run; "
            f"{s['cycles_per_step']:g} loading cycles a step after a transient of {s['transient_cycles']:g}, ν = {nu:g}, "
            f"{cfg['chain']['law']}, {cfg['chain']['ends']} ends, seeds 1–{s['seeds']}) for ℓ = "
            f"{', '.join(f'{e:g}' for e in s['ells'])} and N = {', '.join(map(str, s['sizes']))}, plus N = round(c ℓ) at "
            f"fixed N/ℓ = {', '.join(f'{c:g}' for c in s.get('continuum', [])) or '–'} (toward the continuum limit "
            f"ℓ → ∞, the chain's length in coupling lengths held fixed). The grid is in units of each ℓ's lone-block "
            f"threshold ν_f*(ℓ) = 1/(2√(1 + 2ℓ²)): ν_f/ν_f* = {grid}. The random start has amplitude "
            f"{s['amplitude']:g}/ℓ² (the same start stress spread at every ℓ: from amplitude 0.1 at ℓ = 10, N = 16 "
            "the spread is "
            "30.6 and takes 10–14 loading cycles to relax, docs/chain.md, \"ℓ scan\"). D is left out at steps where some "
            f"seed's event lasted more than {s.get('longest_event', 0.5):g} loading cycles (merged slides). Located as in the "
            "section above (crossing.locate: ν_½ with bootstrap and grid errors, ν_χ, W), here in units of ν_f*; "
            f"{st['runs']} runs, {st['events']} events, {st['cpu']:.0f} CPU s in all."),
        Table(["ℓ", "N", "N/ℓ", "ν_f*", "seeds", "ν_½/ν_f*", "ν_½", "ν_χ/ν_f*", "W/ν_f*",
               "D: smallest ν_f → minimum", "left out (ν_f/ν_f*, up)", "CPU s"], rows),
        Figure("fig_ell_scan.png", "Left: D on the up branch (mean over seeds ± standard error) against ν_f/ν_f*(ℓ), "
               "colour by ℓ; circles and solid lines N ≥ 16, squares and dotted lines N < 16 (fainter for smaller N); "
               "steps left out are gaps; gray: ν_f = ν_f*. Right: ν_½/ν_f*(ℓ) against N (± bootstrap and grid error "
               "in quadrature), gray: ν_f*.",
               alt="D against nu_f over nu_f* per ell and N, and the located transition"),
        Paragraph("Per ℓ, the location against N (sizes of the scan, N > 1) by ν_c(N) = ν_∞ + a/N and the words of "
                  "the section above (crossing.location_words: **approaches ν_f*** when ν_∞ is within 2σ of ν_f*(ℓ) "
                  "and beyond 2σ of 1/2; undecided with fewer than 3 located sizes or χ²/dof > 2):"),
        Table(["ℓ", "ν_f*", "ν_∞/ν_f*", "lone block at this ν: ν_½/ν_f* (chain ν_∞ − it, in σ); ν_χ/ν_f*", "reading"], fit_rows),
        Paragraph("The lone block's column is the reference for a chain whose transition only follows the lone "
                  f"block: its k·P = Δ(ν/√k, ν_f/(2ν_f*)) at ν = {nu:g} on the same grid, located by the same half-way "
                  "crossing and steepest descent. Its stick-slip branch is no plateau (k·P = "
                  + ", ".join(f"{st['fits'][f'{e:g}']['lone'][2]:.2f}" for e in s["ells"])
                  + f" at {st['ratios'][0]:g} ν_f* for ℓ = {', '.join(f'{e:g}' for e in s['ells'])}, falling all the way to "
                  "ν_f*), so both locators put its fall below ν_f* on this grid, the bias the single block's calibration "
                  "shows. Rule: the chain's transition lies **above the lone block's** when ν_∞ − 2σ exceeds both of the "
                  "lone block's locations: " + "; ".join(
                      f"ℓ = {e:g}: " + ("above" if math.isfinite(st["fits"][f"{e:g}"]["fit"]["nu_inf"]) and
                                      (st["fits"][f"{e:g}"]["fit"]["nu_inf"] - 2 * st["fits"][f"{e:g}"]["fit"]["nu_inf_sigma"])
                                      / star(e) > max(st["fits"][f"{e:g}"]["lone"][:2]) else "not shown above")
                      for e in s["ells"]) + "."
                  + steps),
        Paragraph("Toward the continuum limit (fixed N/ℓ, ℓ growing; successive ℓ compared, difference in units of the "
                  "combined σ; three ℓ values are not enough for a fit of the approach, none is made): "
                  + ("; ".join(cont) if cont else "no fixed-N/ℓ pair with located transitions.")
                  + span + ". The chains here have no viscous term: Mori & Kawamura, whose continuum limit of the 1D "
                  "model takes a block-size parameter a → 0, write (arXiv 0807.4588, abstract, arxivlens.com) “The "
                  "Kelvin viscosity term is introduced so that the model dynamics possesses a sensible continuum "
                  "limit.” — so ℓ → ∞ here is the limit of this model, not theirs.")],
        level=3)]


def ell_scan_figure(out, st: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ._study_figures import _NO_SOFTWARE

    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    colours = {}
    for r in st["rows"]:
        c = colours.setdefault(r["ell"], f"C{len(colours)}")
        ax[0].errorbar(st["ratios"], r["d_up"], yerr=r["se_up"], color=c, ms=3, capsize=2,
                       fmt="o-" if r["n"] >= 16 else "s:", alpha=0.4 + 0.6 * min(r["n"], 64) / 64,
                       label=f"ℓ = {r['ell']:g}, N = {r['n']}")
        if math.isfinite(r["half"]["value"]):
            ax[1].errorbar(r["n"], r["half"]["value"], yerr=r["half"]["sigma"], fmt="o", color=c, capsize=3,
                           label=f"ℓ = {r['ell']:g}" if r["ell"] not in [q["ell"] for q in st["rows"][:st["rows"].index(r)]
                                                                          if math.isfinite(q["half"]["value"])] else None)
    ax[0].axvline(1.0, color="gray", lw=0.8)
    ax[0].set(xlabel="ν_f / ν_f*(ℓ)", ylabel="D (up branch)", yscale="log", title="order parameter, ν_f in units of ν_f*")
    ax[1].axhline(1.0, color="gray", lw=0.8, label="ν_f*")
    ax[1].set(xscale="log", xlabel="N", ylabel="ν_½ / ν_f*(ℓ)", title="located transition (half-way crossing)")
    ax[0].legend(fontsize=6, ncol=2), ax[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(Path(out) / "fig_ell_scan.png", dpi=110, metadata=_NO_SOFTWARE)
    plt.close(fig)
