"""The chain report's "Finite-size scaling of a defined transition": the statistics (crossing.py on the
stored D(ν_f) of the sweeps), their section, figure and the verdict sentences that replace the "largest
change between neighbouring ν_f" readings. Everything is recomputed from data.json at each rendering."""

from __future__ import annotations

import math

from ._study_text import _pm, fss_words
from .analysis import finite_size_fit
from .crossing import PLATEAU_FRACTION, WINDOW, locate, location_fit, location_words

__all__ = ["transition_evidence", "transition_figure", "transition_section", "transition_stats"]

SAMPLES, SEED = 2000, 1


def transition_stats(data: dict) -> dict:
    """Per (ν, N, branch): crossing.locate of D; on the up branch of the main ν the FSS fits of ν_½, ν_χ
    (location_fit), W and the window fraction (analysis.finite_size_fit) over the chains (N > 1)."""
    import tomllib

    cfg = tomllib.loads(data["workflow"])
    sweeps = [(float(cfg["chain"]["nu"]), data["sweeps"]["table"])]
    if data.get("sweeps_small_nu", {}).get("table"):
        sweeps.append((float(cfg["sweep_small_nu"]["nu"]), data["sweeps_small_nu"]["table"]))
    rows = []
    for nu, table in sweeps:
        for r in table:
            d = r["slip_per_block"]
            for br in ("up", "down"):
                rows.append({"nu": nu, "n": r["n"], "branch": br, "seeds": r["seeds"],
                             **locate(r["nu_f"], d[br], d["se_" + br], samples=SAMPLES, seed=SEED)})
    fits = {}
    for nu, _ in sweeps:
        ch = [r for r in rows if r["nu"] == nu and r["branch"] == "up" and r["n"] > 1]
        ns = [r["n"] for r in ch]
        fits[f"{nu:g}"] = {
            "half": location_fit(ns, [r["half"]["value"] for r in ch], [r["half"]["sigma"] for r in ch]),
            "peak": location_fit(ns, [r["peak"]["value"] for r in ch], [r["peak"]["sigma"] for r in ch]),
            "width": finite_size_fit(ns, [r["width"]["value"] for r in ch], [r["width"]["sigma"] for r in ch]),
            "window": finite_size_fit(ns, [r["window"]["value"] for r in ch], [r["window"]["sigma"] for r in ch])}
    grid = data["sweeps"]["table"][0]["nu_f"]
    ell = float(cfg["chain"]["ell"])
    return {"rows": rows, "fits": fits, "nus": [nu for nu, _ in sweeps], "spacing": float(grid[1] - grid[0]),
            "star": 0.5 / math.sqrt(1 + 2 * ell**2)}


def _loc(q: dict) -> str:
    if math.isfinite(q["value"]):
        return f"{_pm(q['value'], q['sigma'])}" + (f" ({100 * q['found']:.0f} %)" if q["found"] < 0.995 else "")
    return f"– ({q['status']})"


def _sharp_words(f: dict) -> tuple[str, str]:
    """W(N) through fss_words: W vanishing with N = the change sharpens, growing = it smears."""
    v, words = fss_words(f)
    return {"vanishes": "sharpens with N", "grows": "smears with N", "persists": "neither sharpens nor smears with N",
            }.get(v, "undecided"), words


def _steplike(row, spacing) -> bool:
    """W not resolved from the grid's spacing (W − 2σ ≤ spacing): on this grid, a step."""
    w = row["width"]
    return math.isfinite(w["value"]) and w["value"] - 2 * w["sigma"] <= spacing


def transition_section(st: dict) -> list:
    from ...report.document import Figure, Paragraph, Section, Table

    star, h = st["star"], st["spacing"]
    rows = [[f"{r['nu']:g}", f"{r['n']}", r["branch"], f"{r['seeds']}", _loc(r["half"]), _loc(r["peak"]),
             _pm(r["width"]["value"], r["width"]["sigma"]), _pm(r["window"]["value"], r["window"]["sigma"]),
             f"{r['drop']:.3f}"] for r in st["rows"]]
    fit_rows = []
    for nu in st["nus"]:
        f = st["fits"][f"{nu:g}"]
        for key, name in (("half", "ν_½ (half-way crossing)"), ("peak", "ν_χ (steepest descent)")):
            v, w = location_words(f[key], star)
            fit_rows.append([f"{nu:g}", name, f"**{v}**: {w}"])
        v, w = _sharp_words(f["width"])
        fit_rows.append([f"{nu:g}", "W (width)", f"**{v}**: {w}"])
        v, w = fss_words(f["window"])
        fit_rows.append([f"{nu:g}", f"change across ν_½ ± {WINDOW:g} / drop", f"**{v}**: {w}"])
    one = [r for r in st["rows"] if r["n"] == 1 and r["branch"] == "up"]
    cal = "; ".join(f"ν = {r['nu']:g}: ν_½ = {r['half']['value']:.3f}, ν_χ = {r['peak']['value']:.3f}" for r in one)
    return [Section("Finite-size scaling of a defined transition", [
        Paragraph(
            "The jump above is the largest difference between neighbouring grid points and sits in a different "
            "interval for each N; here the transition is located by two definitions that do not depend on which "
            "interval wins (crossing.py), on the D(ν_f) tabulated above (seed means ± standard errors): "
            "**ν_½**, where D crosses half-way between its value at the smallest ν_f (stick-slip) and its lower "
            f"plateau (the mean of the points within {100 * PLATEAU_FRACTION:g} % of the drop above the minimum, past "
            "the crossing), by linear interpolation; **ν_χ**, the peak of the susceptibility-like −dD/dν_f "
            "(differences at the interval midpoints), at the vertex of the parabola through the largest and its "
            "two neighbours. Errors: a parametric bootstrap over D's error bars (2000 draws, seed 1; each D_i from "
            "a normal of its standard error; σ the draws' spread; the percentage is the share of draws that give "
            "a location at all, shown when below 100 %); for ν_½ the interpolation's own error (the same bracket "
            "interpolated in ln D) is added in quadrature, the only error at N = 1 (deterministic); ν_χ, W and the "
            "window carry the draws' spread only (0 at N = 1). The change's sharpness: **W** = drop / largest −dD/dν_f, the "
            "ν_f range a straight ramp of the same steepest slope needs (a step the grid does not resolve gives "
            f"W = the spacing {h:g}), and the fall of D across the fixed window ν_½ ± {WINDOW:g} as a fraction of the "
            "drop (1: the whole change inside the window). Where D has no lower plateau on the grid (fewer than "
            f"two points within {100 * PLATEAU_FRACTION:g} % of the drop above the minimum) no crossing, W or "
            "window is given: the grid (or the steps D could be kept at) is too short there, and no number is made up."),
        Paragraph(
            f"Calibration on the single block, whose transition lies at ν_f = 1/2 as ν → 0 (docs/physics.md): {cal}. "
            "Its stick-slip branch is not a plateau (D falls all the way from ν_f = 0.15), which pulls ν_½ far below "
            "the transition; ν_χ is the closer locator there. For the chains D falls steeply over a narrower range, "
            "so the two locators are closer, but ν_½ is biased low in the same way."),
        Table(["ν", "N", "branch", "seeds", "ν_½", "ν_χ", "W", f"change across ν_½ ± {WINDOW:g} / drop", "drop of D"],
              rows),
        Figure("fig_transition.png", "Left: the located transition on the up branch, ν_½ (solid) and ν_χ (dashed) at "
               "each ν (± the table's σ; N = 1 is the single block), gray: ν_f* (solid) and 1/2 (dotted). Right: the "
               "width W (± the table's σ), dotted: the grid spacing 0.05, the width of a step the grid cannot resolve.",
               alt="transition location and width against N"),
        Paragraph(
            "Fits over the chains' up branches (N > 1): the location by ν_c(N) = ν_∞ + a/N (weighted least "
            "squares; a shift ∝ 1/volume, the form usually assumed at a first-order transition, with the chain's "
            "volume N — an assumption of this report, not a result read in a source here); W and the window fraction by analysis.finite_size_fit (A N^−θ against a "
            f"constant). Rules for the words: the location **approaches ν_f*** (= {star:.4f}) when ν_∞ is within "
            "2σ of ν_f* and more than 2σ from 1/2, **approaches 1/2** the other way round, **undecided** when "
            "within 2σ of both, or with fewer than 3 located sizes, or χ²/dof > 2 (crossing.location_words); W "
            "**sharpens with N** when it vanishes with N, **smears with N** when it grows, **neither** when it "
            "persists, by the rules of _study_text.fss_words; the change counts as **step-like** at an N when "
            f"W − 2σ ≤ the grid spacing {h:g} (the grid cannot tell it from a step)."),
        Table(["ν", "quantity", "reading"], fit_rows), Paragraph(_caveat(st))], level=3)]


def _caveat(st: dict) -> str:
    """What the location readings carry: ν_½'s bias (seen on the single block) and where ν_χ sits."""
    star = st["star"]
    parts = []
    for nu in st["nus"]:
        pk = [r for r in st["rows"] if r["nu"] == nu and r["branch"] == "up" and r["n"] > 1
              and math.isfinite(r["peak"]["value"])]
        if pk:
            parts.append(f"ν = {nu:g}: " + ", ".join(f"N = {r['n']}: {r['peak']['value']:.3f} "
                                                    f"({100 * (r['peak']['value'] / star - 1):+.0f} %)" for r in pk))
    one = next((r for r in st["rows"] if r["n"] == 1 and r["branch"] == "up"), None)
    located = [r for r in st["rows"] if r["n"] > 1 and r["branch"] == "up" and math.isfinite(r["half"]["value"])]
    below = all(max(r["half"]["value"] + 2 * r["half"]["sigma"],
                    r["peak"]["value"] + 2 * r["peak"]["sigma"] if math.isfinite(r["peak"]["value"]) else 0) < 0.5
                for r in located)
    missing = sorted({r["n"] for r in st["rows"] if r["n"] > 1 and r["branch"] == "up" and r["nu"] == st["nus"][0]
                      and not math.isfinite(r["half"]["value"])})
    return ("Reading the locations: ν_½ carries the bias the single block shows"
            + (f" ({one['half']['value']:.2f} for a transition at 1/2)" if one else "") + ", so "
            "its approach to ν_f* is a statement about the half-way point of a sloping curve, not that the "
            "transition sits at ν_f*; ν_χ, the locator that finds the single block's transition nearer 1/2, puts the "
            "chains' steepest fall above ν_f* (" + "; ".join(parts) + "), where finite ν also puts the lone block's "
            "own crossing (the threshold table: above ν_f* at every ν, closing as ν → 0)."
            + (" Every located chain transition (both locators, +2σ) lies below the uniform mode's 1/2." if below else "")
            + (f" N = {', '.join(map(str, missing))} has no lower plateau on its grid (D is left out where the chain "
               "slides for cycles), so the trend in N rests on the smaller chains." if missing else ""))


def transition_figure(out, st: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ._study_figures import _NO_SOFTWARE

    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    drawn = [0, 0]  # points per panel: a log axis with no data has no limits (small studies locate nothing)
    for nu, mk in zip(st["nus"], ("o", "s")):
        for key, ls, name in (("half", "-", "ν_½"), ("peak", "--", "ν_χ")):
            rs = [r for r in st["rows"] if r["nu"] == nu and r["branch"] == "up" and math.isfinite(r[key]["value"])]
            ax[0].errorbar([r["n"] for r in rs], [r[key]["value"] for r in rs], yerr=[r[key]["sigma"] for r in rs],
                           fmt=mk + ls, ms=4, capsize=3, label=f"{name}, ν = {nu:g}")
            drawn[0] += len(rs)
        rs = [r for r in st["rows"] if r["nu"] == nu and r["branch"] == "up" and math.isfinite(r["width"]["value"])]
        drawn[1] += len(rs)
        ax[1].errorbar([r["n"] for r in rs], [r["width"]["value"] for r in rs], yerr=[r["width"]["sigma"] for r in rs],
                       fmt=mk + "-", ms=4, capsize=3, label=f"W, ν = {nu:g}")
    ax[0].axhline(st["star"], color="gray", lw=0.8, label="ν_f* = 1/(2√k)")
    ax[0].axhline(0.5, color="gray", lw=0.8, ls=":", label="1/2")
    ax[1].axhline(st["spacing"], color="gray", lw=0.8, ls=":", label="grid spacing (a step)")
    ax[0].set(xlabel="N", ylabel="ν_f", title="transition location (up branch; N = 1: the single block)")
    ax[1].set(xlabel="N", ylabel="W = drop / max(−dD/dν_f)", title="width of the change")
    for a, n, log in ((ax[0], drawn[0], ("x",)), (ax[1], drawn[1], ("x", "y"))):
        if n:
            a.set(**{f"{k}scale": "log" for k in log})
        else:
            a.text(0.5, 0.5, "no transition located on this grid", transform=a.transAxes, ha="center", va="center")
    ax[0].legend(fontsize=7), ax[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "fig_transition.png", dpi=110, metadata=_NO_SOFTWARE)
    plt.close(fig)


def transition_evidence(st: dict) -> dict:
    """Verdict sentences and words for Vasconcelos' chain claim (first order persists) and Sakaguchi's
    (continuous in long chains). Rules: Sakaguchi **supported** when W smears with N at the main ν;
    **contradicted** when some chain is step-like and W does not smear; Vasconcelos' chain claim the
    other way round; **undecided** otherwise."""
    star, h = st["star"], st["spacing"]
    out = {}
    per_nu = []
    for nu in st["nus"]:
        ch = [r for r in st["rows"] if r["nu"] == nu and r["branch"] == "up"]
        f = st["fits"][f"{nu:g}"]
        lw, lt = location_words(f["half"], star)
        pw, pt = location_words(f["peak"], star)
        sw, stxt = _sharp_words(f["width"])
        step = [r["n"] for r in ch if r["n"] > 1 and _steplike(r, h)]
        per_nu.append((nu, sw, step))
        out[f"{nu:g}"] = (
            f"at ν = {nu:g}: ν_½: " + "; ".join(f"N = {r['n']}: {_loc(r['half'])}" for r in ch)
            + f" (fit: **{lw}**, {lt}); ν_χ: " + "; ".join(f"N = {r['n']}: {_loc(r['peak'])}" for r in ch)
            + f" (fit: **{pw}**); W: " + "; ".join(f"N = {r['n']}: {_pm(r['width']['value'], r['width']['sigma'])}"
                                                 for r in ch)
            + f" (**{sw}**: {stxt}); step-like (W − 2σ ≤ {h:g}) at N = {', '.join(map(str, step)) or 'none'}")
    nu0, sw0, step0 = per_nu[0]
    if sw0 == "smears with N":
        sak, vas = "supported", "contradicted"
    elif step0 and sw0 != "undecided":
        sak, vas = "contradicted", "supported"
    else:
        why = (f"at ν = {nu0:g} no chain's change is step-like (W ≥ {h:g} + 2σ) and W {sw0}: a smeared change "
               "whose N-trend cannot tell a persisting first-order jump from one that turns continuous")
        if len(per_nu) > 1:
            nu1 = per_nu[1][0]
            w0 = {r["n"]: (r["width"]["value"], r["width"]["sigma"]) for r in st["rows"]
                  if r["nu"] == nu0 and r["branch"] == "up"}
            w1 = [(r["n"], r["width"]["value"], r["width"]["sigma"]) for r in st["rows"]
                  if r["nu"] == nu1 and r["branch"] == "up" and r["n"] > 1 and r["n"] in w0]
            # the ratio and its error (first-order propagation of both W's bootstrap σ)
            rs = [(w / w0[n][0], w / w0[n][0] * math.hypot(s / w, w0[n][1] / w0[n][0])) for n, w, s in w1
                  if w > 0 and math.isfinite(w / w0[n][0])]
            ratio = [q for q, _ in rs]
            if ratio:
                why += (f"; at ν = {nu1:g} W is {min(ratio):.2f}–{max(ratio):.2f}× its ν = {nu0:g} value "
                        f"(N = {', '.join(str(n) for n, _, _ in w1)}; ratio ± σ "
                        + ", ".join(f"{q:.2f} ± {e:.2f}" for q, e in rs) + ")"
                        + (": the change sharpens as ν decreases (every ratio + 2σ < 1), as a jump rounded by ν "
                           "does; a continuous change rounded by ν also sharpens, down to its own width, so this "
                           "alone does not decide between them" if all(q + 2 * e < 1 for q, e in rs) else "")
                        + f"; at ν = {nu1:g} only N ≤ {max(n for n, _, _ in w1)} was run, too few sizes for a "
                        "trend in N")
        sak = vas = "undecided: " + why
    return {"sentences": out, "sak": sak, "vas": vas}
