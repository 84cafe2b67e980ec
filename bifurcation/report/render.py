"""Build the report: analysis of the stores → figures (PNG) → ``REPORT.md`` and a self-contained
``report.html`` (figures embedded as base64, no external references).

The document is assembled once as typed blocks (``report.document``: sections, paragraphs, tables,
figures, lists) and rendered twice, to Markdown and to HTML, so the two always say the same thing. Nothing in it depends on
the wall clock, so the same stores give the same report.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import figures as F
from .document import Figure, Heading, Items, Paragraph, Section, Table, to_html, to_markdown
from ..errors import shown_path

__all__ = ["ReportData", "analyse", "fit_results", "fit_tables", "paper_claims_table", "stability_reruns",
           "write_report"]

LAWS = ("piecewise-linear", "carlson-langer")
FIT_NU_F = (0.2, 0.3, 0.4)
EXTRAPOLATE_NU_F = (0.2, 0.3, 0.4, 0.5)
_FIG_NU = 1e-9
_BAND = (0.44, 0.56)
_MIN_SERIES = 20   # points along ν for a fit; along ν_f for a curve
#: ν_f of the Fig. 2 circles: the engine's direct limit, drawn over the line of Eq. (18).
_FIG2_LIMIT_NU_F = np.round(np.linspace(0.05, 0.5, 10), 8)


@dataclass
class ReportData:
    """Everything the report shows, computed from the stores (``computed_in_process`` lists what no
    store held and was computed with ``bifurcation.slip`` instead)."""

    sources: list
    extrapolations: dict = field(default_factory=dict)   # (law, ν_f) → ExtrapolationResult
    period_fits: list = field(default_factory=list)
    claims: tuple = ()
    curves: dict = field(default_factory=dict)           # law → {ν: (ν_f, Δ)} over (0, 1)
    band_curves: dict = field(default_factory=dict)      # law → {ν: (ν_f, Δ)} near 1/2
    limit_curves: dict = field(default_factory=dict)     # law → (ν_f, Δ0) over (0, 1/2]
    limit_points: dict = field(default_factory=dict)     # law → (ν_f, Δ0): engine limit, Fig. 2 circles
    computed_in_process: list = field(default_factory=list)
    reruns: list = field(default_factory=list)           # (extrapolations, period_fits) on perturbed data


# -- analysis -------------------------------------------------------------------------------------------
def _curves(sources, law, *, span=(0.1, 0.9), band=None, min_points=_MIN_SERIES):
    """Δ along ν_f at every stored ν whose series spans ``span`` (or has ``min_points`` inside ``band``)."""
    from ..analysis import coordinate_values, series_along_nu_f

    out = {}
    for nu in coordinate_values(sources, law, "nu"):
        s = series_along_nu_f(sources, law, nu)
        if band is not None:
            m = (s.x >= band[0]) & (s.x <= band[1])
            if m.sum() >= min_points:
                out[nu] = (s.x[m], s["delta"][m])
        elif len(s) >= min_points and s.x.min() <= span[0] and s.x.max() >= span[1]:
            out[nu] = (s.x, s["delta"])
    return out


def _decades(curves, wanted=(1e-3, 1e-6, 1e-9, 1e-12, 1e-15)):
    """At most one curve per wanted ν (the nearest stored ν within a factor 1.5)."""
    out = {}
    for w in wanted:
        near = [nu for nu in curves if abs(math.log(nu / w)) < math.log(1.5)]
        if near:
            nu = min(near, key=lambda nu: abs(math.log(nu / w)))
            out[nu] = curves[nu]
    return out


def _fallback_curves(law, nus):
    from ..analysis._data import _GOOD
    from ..engine import slip

    nu_f = np.round(np.concatenate([np.arange(0.01, 1.0, 0.01), np.arange(0.481, 0.52, 0.002)]), 6)
    nu_f = np.unique(nu_f)
    r = slip(law, nu=np.asarray(nus)[:, None], nu_f=nu_f[None, :], batch=1)   # scalar: committed digits
    out = {}
    for i, nu in enumerate(nus):
        ok = np.isin(r.status[i], _GOOD)
        out[float(nu)] = (nu_f[ok], r.delta[i][ok])
    return out


def _engine_limit(law, nu_f):
    """The engine's direct ν → 0 limit Δ0 at ``nu_f`` (double), where it is finite."""
    from ..engine import limit

    r = limit(law, nu_f=nu_f)
    ok = np.isfinite(r.delta0)
    return nu_f[ok], r.delta0[ok]


def _limit_curve(law):
    """Δ0(ν_f) over (0, 1/2]: Eq. (18) for the piecewise-linear law (the engine's limit matches it: the
    Fig. 2 circles), the engine's direct limit for any other law."""
    from ..theory import delta0_piecewise_linear

    # finer towards 1/2, where Δ0(ν_f) turns steeply down before the jump
    nu_f = np.unique(np.round(np.concatenate([np.linspace(0.01, 0.5, 50), np.linspace(0.44, 0.5, 25),
                                              0.5 - np.geomspace(1e-4, 1e-2, 9)]), 8))
    if law == "piecewise-linear":
        return nu_f, delta0_piecewise_linear(nu_f)
    return _engine_limit(law, nu_f)


def fit_results(sources, *, in_process=None, delta0=None):
    """The extrapolations ((law, ν_f) → result) and recurrence-time fits the report shows, from
    ``sources`` or, for a series they lack, the in-process ``FALLBACK_GRID`` (``in_process`` is told).

    ``delta0``: the direct limits by (law, ν_f), to skip computing them again (the perturbed reruns).
    """
    from ..analysis import FALLBACK_GRID, extrapolate_delta, fallback_grid, fit_period
    from ..errors import InputError

    def along_nu(fn, law, nu_f, **options):
        try:
            return fn(sources, law, nu_f, **options)
        except InputError:   # no store holds this series
            if in_process is not None:
                in_process(FALLBACK_GRID)
            return fn(fallback_grid(), law, nu_f, **options)

    extrapolations, fits = {}, []
    for law in LAWS:
        for nu_f in EXTRAPOLATE_NU_F:
            extrapolations[(law, nu_f)] = along_nu(extrapolate_delta, law, nu_f, direct=delta0 is None)
        for nu_f in FIT_NU_F:   # Δ0 of T − Δ0/ν: the direct limit the extrapolation already computed
            d0 = delta0[(law, nu_f)] if delta0 is not None else extrapolations[(law, nu_f)].delta0_direct
            fits.append(along_nu(fit_period, law, nu_f, delta0=d0))
    return extrapolations, fits


def stability_reruns(sources, extrapolations) -> list:
    """``fit_results`` on copies of the data perturbed at the size of a change of CPU (``_stable``)."""
    from ..analysis import fallback_grid
    from . import _stable

    delta0 = {key: ex.delta0_direct for key, ex in extrapolations.items()}
    out = []
    for seed in _stable.SEEDS:
        perturbed = [_stable.perturb(ds, seed) for ds in sources] or [_stable.perturb(fallback_grid(), seed)]
        out.append(fit_results(perturbed, delta0=delta0))
    return out


def analyse(sources) -> ReportData:
    """Run every analysis the report shows; what the stores lack is computed in process."""
    from ..analysis import claims_table

    data = ReportData(sources=list(sources))

    def in_process(what):
        if what not in data.computed_in_process:
            data.computed_in_process.append(what)

    data.extrapolations, data.period_fits = fit_results(data.sources, in_process=in_process)
    data.reruns = stability_reruns(data.sources, data.extrapolations)
    for law in LAWS:
        curves = _decades(_curves(data.sources, law))
        if not any(abs(math.log10(nu / _FIG_NU)) < 1e-6 for nu in curves):
            curves.update(_fallback_curves(law, [1e-3, 1e-6, 1e-9, 1e-12]))
            data.computed_in_process.append(f"Δ along ν_f at ν = 1e-3, 1e-6, 1e-9, 1e-12 ({law})")
        data.curves[law] = curves
        band = _decades(_curves(data.sources, law, band=_BAND, min_points=10))
        if not band:   # no store has a band near 1/2: cut it out of the curves over (0, 1)
            inside = {nu: (x >= _BAND[0]) & (x <= _BAND[1]) for nu, (x, _) in curves.items()}
            band = {nu: (x[inside[nu]], d[inside[nu]]) for nu, (x, d) in curves.items()}
        data.band_curves[law] = band
        data.limit_curves[law] = _limit_curve(law)
    data.limit_points["piecewise-linear"] = _engine_limit("piecewise-linear", _FIG2_LIMIT_NU_F)
    data.claims = claims_table(data.sources, extrapolations=data.extrapolations[("carlson-langer", 0.5)],
                               period_fits=data.period_fits)
    for claim in data.claims:
        if claim.fallback:
            in_process(claim.fallback)
    return data


# -- the document ---------------------------------------------------------------------------------------
def _make_figures(data: ReportData, out: Path) -> list[tuple[str, str]]:
    from ..analysis.extrapolate import PAPER_CL_HALF
    from ..analysis.claims import ROUNDING
    from ..analysis.period_fit import DEFAULT_RELATIVE_ERROR
    from ..theory import delta0_piecewise_linear

    made = []
    pl, cl = data.curves.get("piecewise-linear", {}), data.curves.get("carlson-langer", {})
    x18 = np.linspace(0.0025, 0.5, 400)
    lx, ld = data.limit_points["piecewise-linear"]
    eq18_dev = float(np.max(np.abs(ld / delta0_piecewise_linear(lx) - 1)))
    fig = F.figure_fig2(pl, lx, ld, x18, delta0_piecewise_linear(x18))
    made.append(("fig2_piecewise_linear.png", fig,
                 "Fig. 2 reproduced: slip Δ vs ν_f for the piecewise-linear law at several ν (lines), the "
                 "paper's Eq. (18) (dashed, with the jump at ν_f = 1/2) and the engine's direct ν → 0 limit "
                 f"(circles). Finite ν rounds the jump; the limit is Eq. (18) to "
                 + (f"{eq18_dev:.0e}" if eq18_dev >= ROUNDING else f"rounding (< {ROUNDING:.0e})") + " (relative)."))
    cx, cd = data.limit_curves["carlson-langer"]
    ex_cl = data.extrapolations.get(("carlson-langer", 0.5))
    fig = F.figure_fig3(cl, cx, cd, ex_cl)
    made.append(("fig3_carlson_langer.png", fig,
                 "Fig. 3 reproduced: Carlson–Langer law at ν = 1e-9 (thick, the paper's ν) and other ν, the "
                 f"direct ν → 0 limit (black) with its jump at 1/2, the paper's extrapolated {PAPER_CL_HALF:g} "
                 "(red cross) and our extrapolation from finite ν (blue)."))
    crit = {law: data.extrapolations[(law, 0.5)] for law in LAWS if (law, 0.5) in data.extrapolations}
    made.append(("critical_extrapolation.png", F.figure_critical(crit),
                 "Δ at ν_f = 1/2 against ε = 1/W(1/(2eν)) (top axis: ν). Convergence is logarithmic in ν; "
                 f"polynomials in ε extrapolate to the direct limit (star). The paper's {PAPER_CL_HALF:g} (red "
                 "cross) is where finite-ν Δ would be at ν ≈ "
                 + _fmt(ex_cl.nu_reaching_paper if ex_cl is not None else None, ".0e")
                 + " (the fitted model), not at ν → 0."))
    made.append(("period_expansion.png", F.figure_period(data.period_fits),
                 "Recurrence time: T − Δ0/ν (Δ0 the direct limit) against ν at ν_f = 0.2, 0.3, 0.4, with the "
                 "fitted expansion (solid) and the paper's logarithm (α − ω) ln(1/ν) alone (dashed). The "
                 "power K ν^−(α−ω)² dominates. Bottom: residuals in units of the data error "
                 f"(≈ {DEFAULT_RELATIVE_ERROR:.0e} T)."))
    made.append(("transition_rounding.png",
                 F.figure_rounding(data.band_curves, data.limit_curves),
                 "Finite-ν rounding of the transition near ν_f = 1/2: Δ vs ν_f at several ν, and the ν → 0 "
                 "limit (black) that jumps to 0 at 1/2. The rounding shrinks only logarithmically in ν."))
    out.mkdir(parents=True, exist_ok=True)
    files = []
    for name, fig, caption in made:
        F.save(fig, out / name)
        files.append((name, caption))
    return files


def _at(ex, nu: float) -> float:
    """Δ of an extrapolation's data at the ν nearest to ``nu``."""
    return float(ex.delta[np.argmin(np.abs(np.log(ex.nu / nu)))])


def _fmt(x, spec=".6g") -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "—"
    return format(x, spec)


def _sci(x: float) -> str:
    """Scientific notation as the text writes it: 1e-3, 2.2e-16."""
    mantissa, exponent = f"{x:e}".split("e")
    return f"{mantissa.rstrip('0').rstrip('.')}e{int(exponent)}"


def _findings(data: ReportData, ex_cl, ex_pl, errata) -> list[str]:
    """The summary bullets, each worded from a computed verdict."""
    from ..analysis.extrapolate import PAPER_CL_HALF

    paper = f"{PAPER_CL_HALF:g}"
    verdict = {c.key: c.verdict for c in data.claims}
    counts: dict = {}
    for c in data.claims:
        counts[c.verdict] = counts.get(c.verdict, 0) + 1
    out = [f"{len(data.claims)} quantitative claims checked: "
           + ", ".join(f"{n} {v}" for v, n in sorted(counts.items(), key=lambda kv: -kv[1])) + "."]
    if ex_cl is not None and ex_pl is not None:
        word = "as claimed" if verdict.get("transition") == "confirmed" else "CONTRARY to the claim (check)"
        out.append(f"The transition at ν_f = 1/2 is discontinuous, {word}: the direct ν → 0 slip at 1/2 is "
                   f"{ex_pl.delta0_direct:.12f} (piecewise-linear; Eq. 18 gives √e) and "
                   f"{ex_cl.delta0_direct:.13f} (Carlson–Langer), and Δ ∝ ν → 0 above 1/2.")
    if ex_cl is not None:
        agree = "agrees with" if ex_cl.consistent else "DISAGREES with"
        judged = "is wrong" if verdict.get("cl_half_0.17") == "refuted" else "holds"
        out.append(f"The paper's Δ = {paper} at ν_f = 1/2 (Carlson–Langer) {judged}: from finite ν we "
                   f"extrapolate {ex_cl.delta0_extrapolated:.5f} ± {ex_cl.uncertainty:.1e}, which {agree} the "
                   f"direct limit {ex_cl.delta0_direct:.10f}; {paper} is "
                   f"{PAPER_CL_HALF / ex_cl.delta0_direct - 1:+.0%} off. "
                   f"Convergence in ν is logarithmic: Δ(1e-9) = {_at(ex_cl, 1e-9):.4f}, "
                   f"Δ(1e-15) = {_at(ex_cl, 1e-15):.4f}, "
                   f"and Δ(ν) comes down to {paper} only near ν ≈ {_fmt(ex_cl.nu_reaching_paper, '.0e')}.")
    if data.period_fits:
        from ..analysis.claims import log_coefficient_check

        within, bound = log_coefficient_check(data.period_fits)
        agree = "within the fits' uncertainties" if within else "NOT within the fits' uncertainties"
        ks = min(f.K for f in data.period_fits), max(f.K for f in data.period_fits)
        out.append(f"T = Δ/ν + t1 is {verdict.get('recurrence_time', '?')}: the coefficient of ln(1/ν) in "
                   f"T − Δ0/ν is α − ω ({agree}, < {bound:.0e} relative, {len(data.period_fits)} fits), but a power "
                   f"K ν^−(α−ω)² (K = {ks[0]:.2f} … {ks[1]:.2f} > 0), absent from the paper, dominates it.")
    by_cause: dict = {}
    for e in errata:
        by_cause.setdefault(e.cause, []).append(e.equation.split(",")[0])
    out.append(f"{len(errata)} errata: " + "; ".join(f"{cause}: {', '.join(dict.fromkeys(eqs))}"
                                                     for cause, eqs in by_cause.items()) + " (table below).")
    return out


def _blocks(data: ReportData, files) -> list:
    """The paper's report as typed blocks (``report.document``): the summary, then one section each."""
    from .. import __version__
    from ..analysis.extrapolate import CRITICAL_ORDERS, CRITICAL_WINDOWS, PAPER_CL_HALF
    from ..analysis.period_fit import DEFAULT_RELATIVE_ERROR, DEFAULT_WINDOWS
    from ..theory import ERRATA

    ex_cl = data.extrapolations.get(("carlson-langer", 0.5))
    ex_pl = data.extrapolations.get(("piecewise-linear", 0.5))
    tables = fit_tables(data.extrapolations, data.period_fits, data.reruns)
    limit = [Paragraph(f"At ν_f = 1/2: polynomials of order {min(CRITICAL_ORDERS)}–{max(CRITICAL_ORDERS)} in "
                       "ε = 1/W(1/(2eν)) (+ ν/ε, ν) over the windows ν ≤ "
                       + ", ".join(_sci(w) for w in CRITICAL_WINDOWS)
                       + "; the estimate is the median, the uncertainty the largest deviation "
                       "from it combined with the largest covariance error. Below 1/2: the expansion of the "
                       "recurrence-time section with Δ0 free. The direct limit is the engine's ν = 0 orbit (quad; "
                       "its error is |quad − double|)."),
             tables["extrapolations"]]
    if ex_cl is not None:
        naive = "; ".join(f"{k}: {v:.4g}" for k, v in ex_cl.naive.items())
        limit += [Paragraph("Carlson–Langer at ν_f = 1/2, every model of the ensemble:"), tables["ensemble"],
                  Paragraph(f"How a value like {PAPER_CL_HALF:g} arises — extrapolations that assume faster than "
                            f"logarithmic convergence, or no extrapolation: {naive}.")]
    recurrence = [
        Paragraph("r = (α − ω)² = λ−/λ+. The slow mode of the start grows to ~ν^(1−r) by the time the fast "
                  "mode has carried the block out, so the expansion holds the powers ν^(j(1−r)+k−1) (with ln(1/ν) "
                  "companions where the eigenvalues depend on ν, and at the resonances λ+ = 9λ− (ν_f = 0.3) "
                  "and 4λ− (ν_f = 0.4), which add ν^(m−1) ln(1/ν), below the data precision for ν ≤ 1e-5). "
                  f"Linear least squares, r fixed, weights 1/({_sci(DEFAULT_RELATIVE_ERROR)} T); the higher terms "
                  "are chosen by the data (smallest model whose residuals are at the data precision) in each "
                  "window ν ≤ " + ", ".join(_sci(w) for w in DEFAULT_WINDOWS)
                  + "; the uncertainty includes the spread over windows."),
        tables["period_fits"], Paragraph(_STABLE_NOTE)]
    prov = [f"bifurcation {__version__}; " + ", ".join(f"{p} {v}" for p, v in _versions().items())]
    for ds in data.sources:
        a = ds.attrs
        prov.append(f"store {shown_path(a.get('store_path', '(in memory)'))}: study {a.get('title', '?')!r}, workflow "
                    f"sha256 {str(a.get('workflow_sha256', '?'))[:16]}, precision {a.get('precision', '?')}, "
                    f"{int(np.prod([ds.sizes[d] for d in ('law', 'nu_f', 'nu') if d in ds.sizes]))} points, "
                    f"written by bifurcation {a.get('version_bifurcation', '?')}")
    prov += [f"computed in process (no store held it): {c}" for c in data.computed_in_process]
    prov.append("Direct ν → 0 limits: bifurcation.limit (engine), quad precision; closed forms: "
                "bifurcation.theory; paper: G. L. Vasconcelos, First-order phase transition in a model for "
                "earthquakes, Phys. Rev. Lett. 76, 4865 (1996), equation numbers as printed there.")
    return [
        Heading("Vasconcelos, PRL 76, 4865 (1996), reproduced and checked", 1),
        Paragraph("A spring-block model with velocity-weakening friction Φ: Ü = νt − U + 1 − Φ(U̇/ν_f). "
                  "The paper claims a first-order (discontinuous) transition from stick-slip to creep at ν_f = 1/2 "
                  "as ν → 0. Each number below is computed by this package (engine, direct ν → 0 limit, fits); "
                  "units: Δ in F0/k, ν and ν_f in V0 = F0/√(mk), times in √(m/k)."),
        Items(_findings(data, ex_cl, ex_pl, ERRATA)),
        Section("Claims", [paper_claims_table(data.claims)]),
        Section("Errata", [Table(["equation", "printed", "corrected", "cause", "evidence"],
                                 [[e.equation, e.printed, e.corrected, e.cause, e.evidence] for e in ERRATA])]),
        Section("Δ(ν → 0): extrapolated from finite ν vs the direct limit", limit),
        Section("Recurrence time: T − Δ0/ν = (α − ω) ln(1/ν) + C0 + K ν^−r + …", recurrence),
        Section("Figures", [Figure(name, caption) for name, caption in files]),
        Section("Provenance", [Items(prov)]),
    ]


def paper_claims_table(claims) -> Table:
    """The paper's claims against what we measure (the paper's report and a store report that holds its laws)."""
    return Table(["where", "the paper says", "we measure", "agreement", "verdict"],
                 [[c.where, f"{c.statement}: {c.paper}", c.measured, c.agreement, c.verdict] for c in claims])


_STABLE_NOTE = ("Digits: heyoka compiles for the host CPU, so the engine's results differ between machines in "
                "their last bits (≤ 1e-14 relative). Each fitted number above is printed only to the digits "
                "that such a change cannot move: the fits were repeated three times on data perturbed by "
                "2.2e-16 relative (the data error the fits assume) and every digit whose unit is less than twice "
                "the largest change was dropped; a number with no such digit is replaced by (machine-dependent), "
                "and a term count that the perturbation changed is marked so. The claims table quotes the same "
                "fits with fewer digits.")


def fit_tables(extrapolations, period_fits, reruns) -> dict:
    """The extrapolation, ensemble and recurrence-time tables as ``{name: Table}``, each fitted
    number cut to its CPU-independent digits (``_stable``) using the perturbed ``reruns``."""
    from ._stable import spread, stable
    from ..analysis.claims import ROUNDING

    def change(kind, key_or_index, name, model=None):
        others = []
        for ex_p, fits_p in reruns:
            item = ex_p[key_or_index] if kind == "ex" else fits_p[key_or_index]
            others.append(item.models[model] if model is not None else item)
        ref = extrapolations[key_or_index] if kind == "ex" else period_fits[key_or_index]
        return spread(ref.models[model] if model is not None else ref, others, name)

    rows = []
    for key, ex in sorted(extrapolations.items()):
        law, nu_f = key
        c = change("ex", key, "delta0_extrapolated")
        # rounding-level numbers (the stick-slip side, where the extrapolation is the direct limit) as the
        # bound they are: their digits (0, 2e-16, 3e-16) are the host CPU's (analysis.claims.ROUNDING)
        small = f"< {ROUNDING:.0e}"
        rows.append([law, f"{nu_f:g}", ex.regime, stable(ex.delta0_extrapolated, c, ".10f"),
                     small if ex.uncertainty < ROUNDING else
                     stable(ex.uncertainty, change("ex", key, "uncertainty"), ".1e"),
                     f"{ex.delta0_direct:.15f}",
                     small if ex.delta0_direct_error < ROUNDING else f"{ex.delta0_direct_error:.0e}",
                     _fmt(ex.paper_value, ".6g") if ex.paper_value is not None else "—",
                     small + " (rounding)" if abs(ex.deviation) < ROUNDING else stable(ex.deviation, c, "+.1e"),
                     "yes" if ex.consistent else "NO"])
    tables = {"extrapolations": Table(["law", "ν_f", "regime", "extrapolated Δ0", "uncertainty", "direct Δ0",
                                       "direct error", "paper", "extrap. − direct", "consistent"], rows)}
    key = ("carlson-langer", 0.5)
    if key in extrapolations:
        ex = extrapolations[key]
        same = all(len(ex_p[key].models) == len(ex.models) for ex_p, _ in reruns)
        tables["ensemble"] = Table(["model", "ν ≤", "points", "Δ0", "std. error", "max residual"],
                              [[m.model, f"{m.nu_max:g}", str(m.n_points),
                                stable(m.delta0, change("ex", key, "delta0", i) if same else math.inf, ".8f"),
                                stable(m.stderr, change("ex", key, "stderr", i) if same else math.inf, ".1e"),
                                stable(m.residual_max, change("ex", key, "residual_max", i) if same else math.inf,
                                       ".1e")] for i, m in enumerate(ex.models)])
    rows = []
    for i, f in enumerate(period_fits):
        terms_moved = any(len(fits_p[i].model) != len(f.model) or fits_p[i].nu_max != f.nu_max
                          for _, fits_p in reruns)

        def st(name, spec, value=None):
            v = getattr(f, name) if value is None else value
            return stable(v, change("fit", i, name), spec)

        rows.append([f.law, f"{f.nu_f:g}", f"{f.exponent_r:.5f}",
                     f"{st('log_coefficient', '.8f')} ± {st('log_coefficient_uncertainty', '.0e')}",
                     f"{f.log_coefficient_expected:.8f}", st("relative_deviation", "+.1e"), st("C0", ".6g"),
                     st("K", ".6g"), st("K2", ".4g"), str(len(f.model)) + (" (machine-dependent)" if terms_moved else ""),
                     f"{f.nu_max:g}", st("residual_max", ".1e"), st("chi_max", ".2f")])
    tables["period_fits"] = Table(["law", "ν_f", "r", "ln coefficient (fit)", "α − ω", "rel. dev.", "C0", "K", "K2",
                                   "terms", "ν ≤", "max |residual|", "max residual/error"], rows)
    return tables


def _versions() -> dict:
    from importlib.metadata import PackageNotFoundError, version

    out = {}
    for p in ("numpy", "heyoka", "matplotlib", "xarray", "zarr"):
        try:
            out[p] = version(p)
        except PackageNotFoundError:
            pass
    return out


def write_report(sources, out, *, data: ReportData | None = None) -> dict:
    """Analyse ``sources`` (Datasets, or store paths) and write the report into directory ``out``.

    Returns the written paths: ``{"markdown": …, "html": …, "figures": [...]}``.
    """
    from ..analysis import load_stores

    sources = list(sources) if isinstance(sources, (list, tuple)) else [sources]
    opened = []
    for s in sources:
        opened.extend(load_stores(s) if isinstance(s, (str, Path)) else [s])
    out = Path(out)
    data = data if data is not None else analyse(opened)
    files = _make_figures(data, out)
    blocks = _blocks(data, files)
    md, page = out / "REPORT.md", out / "report.html"
    md.write_text(to_markdown(blocks), encoding="utf-8")
    page.write_text(to_html(blocks, out), encoding="utf-8")
    return {"markdown": md, "html": page, "figures": [out / n for n, _ in files], "data": data}
