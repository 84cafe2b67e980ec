"""The two-parameter bifurcation diagram of the study: (η, κ) planes with the Hopf curve, the Bautin
points, the fold-of-cycles curves from each Bautin point, and what happens in each region.

η = M V_lp²/(a Dc) (the normalised mass) and κ = k/k_c(η). The Hopf curve is κ = 1 in these
coordinates by construction; it is computed anyway (``two_parameter.hopf_curve``: the root of
Re λ_max from the eigenvalues, against the closed form). Each Bautin point of the study's scan starts a
fold-of-cycles curve (``two_parameter.fold_curve``): continued from the fold that a branch of the study
flags at its η (a subcritical inertial branch of the same law) up to the Bautin point and down towards
η → 0; every fold is checked by a direct run (the period of a second turn, an independent step grid).
The regions are labelled by runs, not by inference: the fate of the perturbed steady slide
(``attractor.fate``) at sample points, and in the bistable band also the stable cycle found there by
Newton on the return map from the fold's cycle (its multipliers inside the unit circle).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Diagram", "FoldCurve", "RegionSample", "basins", "compute", "figure", "fold_curves", "region_samples", "section"]

A, B, DC, V_LP = 0.01, 0.015, 0.01, 1.0
#: the fold curve stops this far below the Bautin point (relative): closer, dμ₁/dκ → 0 and the fold
#: is no longer located to 1e-9 (at 4e-4 below the PRZ point Newton did not converge)
BAUTIN_GAP = 2e-3
UP_POINTS = 52
DOWN_POINTS = 20
ETA_LOW = 2e-3


@dataclass(frozen=True)
class FoldCurve:
    state_law: str
    eta_bautin: float
    start: str                   # the branch whose flagged fold started the curve
    points: tuple                # two_parameter.FoldPoint, sorted by η
    period_checks: tuple         # |T_direct/T − 1| of each point (second turn of a direct run)
    seconds: float


def _period_check(f, law) -> float:
    from .simulate import run_spec
    from .spec import SliderSpec, load_history

    spec = SliderSpec(a=A, b=B, dc=DC, state_law=law, k=f.k, mass=f.eta * A * DC / V_LP ** 2)
    r = run_spec(spec, load_history(V_LP), [0.0, 2.5 * f.period], ln_v0=math.log(V_LP), ln_theta0=[f.w[0]],
                 z0=f.w[1], thresholds=[V_LP])
    ups = [c[0] for c in r.crossings if c[2] > 0]
    return abs((ups[1] - ups[0]) / f.period - 1) if len(ups) > 1 else math.nan


def fold_curves(results, bautin: dict, echo=print) -> list:
    """One fold-of-cycles curve per finite Bautin point in ``bautin`` ({law: η_B})."""
    import time

    from .two_parameter import fold_curve

    out = []
    for law, eta_b in bautin.items():
        if not math.isfinite(eta_b):
            continue
        starts = [r for r in results if r["spec"].state_law == law and r["spec"].parameter == "kappa"
                  and 0 < r["spec"].eta < eta_b and r["branch"].folds and r["spec"].damping == 0
                  and (r["spec"].a, r["spec"].b, r["spec"].dc, r["spec"].v_lp) == (A, B, DC, V_LP)]
        if not starts:
            echo(f"  fold curve {law}: no branch of the study flags a fold below η_B = {eta_b:.6g}")
            continue
        t0 = time.perf_counter()
        r = starts[0]
        p = r["branch"].points[r["branch"].folds[0]]
        eta0 = r["spec"].eta
        up = fold_curve(list(np.linspace(eta0, eta_b * (1 - BAUTIN_GAP), UP_POINTS)), p.w, p.kappa, state_law=law)
        down = fold_curve(list(np.geomspace(eta0, ETA_LOW, DOWN_POINTS + 1)), p.w, p.kappa, state_law=law)[1:]
        pts = sorted(up + down, key=lambda f: f.eta)
        checks = tuple(_period_check(f, law) for f in pts)
        out.append(FoldCurve(law, eta_b, r["spec"].label, tuple(pts), checks, time.perf_counter() - t0))
        ok = sum(f.status == "ok" for f in pts)
        echo(f"  fold curve {law}: {len(pts)} folds ({ok} converged) η in [{pts[0].eta:.4g}, {pts[-1].eta:.6g}], "
             f"max period check {max(checks):.1e}, {time.perf_counter() - t0:.1f} s")
    return out


@dataclass(frozen=True)
class RegionSample:
    state_law: str
    eta: float
    kappa: float
    region: str                  # the label the diagram gives the region
    fate: str                    # attractor.fate's kind from steady sliding + 1e-2 in ln V
    cycle_multiplier: float      # bistable band: largest |μ| of the coexisting cycle (NaN elsewhere)
    cycle_span: float            # its ln V_max − ln V_min

    @property
    def as_labelled(self) -> bool:
        """The run agrees with the label: a cycle below κ = 1, steady sliding above; in the bistable band
        steady sliding from the small perturbation and a coexisting cycle with its multipliers inside 1."""
        if self.region == "stable cycle":
            return self.fate == "cycle"
        if self.region == "bistable":
            return self.fate == "steady" and self.cycle_multiplier < 1 and self.cycle_span > 0
        return self.fate == "steady"


#: (law, η, κ, region) at which the regions are checked; κ chosen off the curves (the fold curves above
#: reach κ − 1 = 0.0060 (aging) and 0.060 (PRZ) at most on [2e-3, η_B])
SAMPLES = (
    ("aging", 0.05, 0.9, "stable cycle"), ("aging", 0.17, 0.9, "stable cycle"),
    ("aging", 0.05, 1.05, "stable steady sliding"), ("aging", 0.17, 1.05, "stable steady sliding"),
    ("aging", 0.03, 1.003, "bistable"),
    ("slip", 0.05, 0.9, "stable cycle"), ("slip", 0.05, 1.05, "stable steady sliding"),
    ("prz", 0.03, 0.9, "stable cycle"), ("prz", 0.15, 0.9, "stable cycle"),
    ("prz", 0.03, 1.2, "stable steady sliding"), ("prz", 0.15, 1.05, "stable steady sliding"),
    ("prz", 0.03, 1.01, "bistable"),
)


def region_samples(curves, samples=SAMPLES) -> list:
    """Run each sample point; in the bistable band find the coexisting stable cycle too."""
    from .attractor import fate
    from .continuation import ReturnMap
    from .hopf import closed_form
    from .spec import SliderSpec

    out = []
    for law, eta, kappa, region in samples:
        mass = eta * A * DC / V_LP ** 2
        probe = SliderSpec(a=A, b=B, dc=DC, state_law=law, k=1.0, mass=mass)
        k_c, omega_c = (float(v) for v in closed_form(probe, V_LP))
        spec = SliderSpec(a=A, b=B, dc=DC, state_law=law, k=kappa * k_c, mass=mass)
        f = fate(spec, V_LP, 2 * math.pi / omega_c, max_steps=2_000_000, t_max=math.inf)
        mult = span = math.nan
        if region == "bistable":
            curve = next(c for c in curves if c.state_law == law)
            near = min(curve.points, key=lambda p: abs(p.eta - eta))
            pmap = ReturnMap(spec, V_LP, t_max=1e3 * 2 * math.pi / omega_c)
            # start outside the fold's cycle (half as far again from steady sliding): Newton goes to
            # the outer, larger cycle, not to the unstable one inside
            w_star = np.array([math.log(probe.laws[0].steady_factor * DC / V_LP), 0.0])
            w = w_star + 1.5 * (np.array(near.w) - w_star)
            for _ in range(20):
                h = 1e-7 * np.maximum(np.abs(w), 1.0)
                J = np.array([(pmap(w + e, spec.k)[0] - pmap(w - e, spec.k)[0]) / (2 * hj)
                              for hj, e in zip(h, np.diag(h))]).T
                r = pmap(w, spec.k)
                dw = np.linalg.solve(J - np.eye(w.size), r[0] - w)
                w = w - dw
                if np.max(np.abs(dw)) < 1e-12 * max(1.0, np.max(np.abs(w))):
                    break
            r = pmap(w, spec.k)
            h = 1e-7 * np.maximum(np.abs(w), 1.0)
            J = np.array([(pmap(w + e, spec.k)[0] - pmap(w - e, spec.k)[0]) / (2 * hj)
                          for hj, e in zip(h, np.diag(h))]).T
            mult, span = float(max(abs(np.linalg.eigvals(J)))), r[2] - r[3]
        out.append(RegionSample(law, eta, kappa, region, f.kind, mult, span))
    return out


def _region_text(ax, x, y, text, **kw):
    ax.text(x, y, text, ha="center", va="center", fontsize=7, transform=ax.transAxes,
            bbox=dict(boxstyle="round,pad=0.2", fc="white", ec="0.7", alpha=0.85), **kw)


def figure(path, results, bautin, curves, samples, fates, cascade=None) -> None:
    """Top: (η, κ − 1) per law. Bottom: ln V_max against κ on the study's branches, and the cascade."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .report import _stable, blew_up

    laws = ("aging", "slip", "prz")
    fig, axes = plt.subplots(2, 3, figsize=(15, 10.5))
    eta_max = 0.2
    for ax, law in zip(axes[0], laws):
        curve = next((c for c in curves if c.state_law == law), None)
        eb = bautin.get(law, math.nan)
        top = max(p.kappa for p in curve.points) - 1 if curve else 0.01
        # κ − 1 on a symmetric log scale: the fold curves (κ_f − 1 from 1e-5 to 0.14) and the sample runs
        # (κ = 0.9 … 1.2) in one panel, linear within ±top/5 where the curves meet κ = 1
        ax.set_yscale("symlog", linthresh=top / 5, linscale=1.5)
        ax.axhline(0.0, color="k", lw=1.5, label="Hopf curve (k_c from the eigenvalues)")
        if curve:
            e = np.array([p.eta for p in curve.points])
            k = np.array([p.kappa for p in curve.points]) - 1
            ax.plot(e, k, "-", color="C3", lw=1.5, label=f"fold of cycles ({len(e)} folds, μ₁ = 1)")
            ax.fill_between(e, 0.0, k, color="C3", alpha=0.15)
        if math.isfinite(eb):
            ax.plot([eb], [0.0], "D", color="C2", ms=7, label=f"Bautin point η = {eb:.6g}")
        for s_ in samples:
            if s_.state_law == law and s_.eta <= eta_max:
                mark = {"steady": "o", "cycle": "s"}.get(s_.fate, "x")
                ax.plot([s_.eta], [s_.kappa - 1], mark, mfc="none", mec="0.1", ms=7)
                if s_.region == "bistable" and math.isfinite(s_.cycle_multiplier):
                    ax.plot([s_.eta], [s_.kappa - 1], "s", mfc="none", mec="0.1", ms=11)
        if any(f["state_law"] == law and blew_up(f) for f in fates):
            ax.plot([0, 0], [-0.2, 0.0], color="C1", lw=6, solid_capstyle="butt",
                    label="η = 0 (quasi-static): V blows up below k_c")
        ax.set_xlim(0, eta_max)
        ax.set_ylim(-0.2, max(3 * top, 0.3))
        ax.set_xlabel("η = M V_lp² / (a Dc)")
        ax.set_ylabel("κ − 1 = k / k_c(η) − 1   (symlog)")
        ax.set_title(f"{law}: a = 0.01, b = 0.015, Dc = 0.01, V_lp = 1", fontsize=9)
        _region_text(ax, 0.22, 0.3, "steady sliding unstable:\nstable cycle (η > 0)")
        if curve:
            _region_text(ax, 0.7, 0.93, "stable steady sliding only")
            b_ = next((s_ for s_ in samples if s_.state_law == law and s_.region == "bistable"), None)
            if b_ is not None:
                ax.annotate("bistable: stable steady sliding\n+ stable cycle, unstable cycle between",
                            (b_.eta, b_.kappa - 1), xytext=(0.6, 0.72), textcoords="axes fraction", fontsize=7,
                            ha="center", arrowprops=dict(arrowstyle="->", color="0.4"),
                            bbox=dict(boxstyle="round,pad=0.2", fc="white", ec="0.7", alpha=0.85))
        else:
            _region_text(ax, 0.55, 0.85, "stable steady sliding (supercritical Hopf:\nno Bautin point, no fold)")
        # below the panel: inside it would cover the runs at κ = 0.9 or 1.05
        ax.legend(fontsize=6.5, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, frameon=False)
    for ax, inertial in ((axes[1][0], True), (axes[1][1], False)):
        for r in results:
            b = r["branch"]
            if b.meta.get("parameter", "kappa") != "kappa" or b.spec.inertial != inertial:
                continue
            k = np.array([p.kappa for p in b.points])
            top = np.array([p.ln_v_max for p in b.points])
            st = np.array([_stable(p) for p in b.points])
            line, = ax.plot(k, top, lw=0.6, alpha=0.4)
            ax.plot(np.where(st, k, np.nan), np.where(st, top, np.nan), "-", color=line.get_color(), lw=2,
                    label=f"{r['spec'].label} ({b.hopf.criticality})")
            ax.plot(np.where(~st, k, np.nan), np.where(~st, top, np.nan), "--", color=line.get_color(), lw=1.5)
            for i in b.folds:
                ax.plot(b.points[i].kappa, b.points[i].ln_v_max, "o", color=line.get_color())
        ax.axvline(1.0, color="k", lw=0.5)
        ax.set_xlabel("κ = k / k_c")
        ax.set_ylabel("ln(V_max / V_lp) over the cycle")
        ax.set_title(("inertial" if inertial else "quasi-static") + " branches in κ\n(solid stable, dashed "
                     "unstable or neutral, dots folds)", fontsize=9)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=6.5)
    ax = axes[1][2]
    if cascade is not None and cascade.loop_maxima:
        ks = [d.kappa for d in cascade.doublings]
        lo_k, hi_k = ks[-1] - 0.3 * (ks[0] - ks[-1]), ks[0] + 0.3 * (ks[0] - ks[-1])
        for j, (n, b) in enumerate(sorted(cascade.branches.items())):
            for p, tops in zip(b.points, cascade.loop_maxima[n]):
                if lo_k <= p.kappa <= hi_k:
                    st = _stable(p)
                    ax.plot([p.kappa] * len(tops), tops, "o" if st else ".", color=f"C{j}", ms=3 if st else 1.5,
                            mfc=f"C{j}" if st else "none")
            ax.plot([], [], "o", color=f"C{j}", ms=3, label=f"period {n}" + (" (stable: filled)" if j == 0 else ""))
        for d in cascade.doublings:
            ax.axvline(d.kappa, color="0.6", lw=0.5)
        ax.set_xlim(lo_k, hi_k)
        ax.set_xlabel("κ = k / k_c")
        ax.set_ylabel("ln(V_max / V_lp) of each loop")
        ax.set_title("two slip-law state variables, quasi-static: period-doubling cascade\n"
                     "(grey lines: located doublings)", fontsize=9)
        ax.legend(fontsize=6.5)
    else:
        ax.axis("off")
    fig.suptitle("Bifurcation diagrams from computed data: Hopf curve, Bautin points, fold-of-cycles curves, "
                 "period doublings (top: markers are checked runs, ○ steady sliding, □ stable cycle)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=100, metadata={"Software": None})
    plt.close(fig)


#: the two-state slip-law slider whose period-1 branch doubles (docs/rate-state.md, "A period doubling")
CASCADE_SLIDER = dict(state_law="slip", a=0.01, b=[0.012, 0.006], dc=[0.01, 0.1], v_lp=1.0)
CASCADE_LEVELS = 5
HOPF_ETAS = (0.0, 0.01, 0.03, 0.1, 0.2)


@dataclass(frozen=True)
class Diagram:
    hopf_dev: dict               # law → max |k_c / closed form − 1| along the Hopf curve in η (40 digits)
    curves: tuple                # FoldCurve per Bautin point
    samples: tuple               # RegionSample
    cascade: object              # doubling.Cascade (or None)
    torus: tuple                 # (label, doubling.TorusScan) per branch scanned
    seconds: float
    basins: dict = None          # quasi-static basins above k_c: see ``basins``


def compute(results, bautin: dict, echo=print, cascade_levels: int = CASCADE_LEVELS) -> Diagram:
    """Everything the diagram and its report section need (module docstring)."""
    import time

    from .continuation import continue_cycles
    from .doubling import cascade, torus_scan
    from .two_parameter import hopf_curve

    t0 = time.perf_counter()
    hopf_dev = {law: hopf_curve("eta", list(HOPF_ETAS), state_law=law, a=A, b=B, dc=DC, v_lp=V_LP).max_rel_dev
                for law in ("aging", "slip", "prz")}
    echo(f"  Hopf curves in η: max rel. dev. from the closed form {max(hopf_dev.values()):.1e}")
    curves = fold_curves(results, bautin, echo)
    # a bistable sample needs its law's fold curve (none when the study's branches are damped: the
    # curves start from undamped folds)
    samples = region_samples(curves, [x for x in SAMPLES if x[3] != "bistable"
                                      or any(c.state_law == x[0] for c in curves)])
    echo(f"  regions: {sum(s.as_labelled for s in samples)}/{len(samples)} sample runs as labelled")
    casc = None
    if cascade_levels:
        parent = continue_cycles(**CASCADE_SLIDER, points=16, max_step=0.3, kappa_range=(0.05, 20),
                                 max_steps=500_000)
        casc = cascade(parent, cascade_levels)
        echo(f"  cascade: doublings at κ = {[round(d.kappa, 9) for d in casc.doublings]}, ratios "
             f"{[round(r, 4) for r in casc.ratios]}, {casc.seconds:.0f} s")
    torus = [(r["spec"].label, torus_scan(r["branch"])) for r in results
             if r["branch"].meta.get("parameter", "kappa") == "kappa"]
    if casc is not None:
        torus += [(f"two slip-law states, period {n}", torus_scan(b)) for n, b in sorted(casc.branches.items())]
    basin = basins(results)
    echo(f"  basins: slip-law Δ_c {[(k, round(lo, 4)) for k, lo, _, _ in basin['slip']]}, aging spikes all "
         f"{set(r[2] for r in basin['aging'])}")
    return Diagram(hopf_dev, tuple(curves), tuple(samples), casc, tuple(torus), time.perf_counter() - t0, basin)


#: κ at which the quasi-static slip law's critical raise of ln θ is bracketed; (κ, Δ) of the aging runs
SLIP_KAPPAS = (1.02, 1.1, 2.0)
AGING_RUNS = ((1.1, 2.0), (1.1, 5.0), (1.5, 5.0), (2.0, 5.0))


def basins(results) -> dict:
    """Quasi-static, above k_c: the slip law's threshold, the aging law's bounded spikes, PRZ's cycle.

    slip: (κ, lo, hi, engine fate at lo) with Δ_c in [lo, hi] by bisection of the slide in slip
    (``basin.critical_in_slip``); aging: (κ, Δ, outcome in slip, peak ln V, engine fate); prz: (κ, Δ_c)
    read off the study's branch of unstable cycles (``basin.critical_perturbation``).
    """
    from .basin import critical_in_slip, critical_perturbation, fate_of_perturbation, in_slip
    from .continuation import continue_cycles

    out = {"slip": [], "aging": [], "prz": []}
    slip = continue_cycles(state_law="slip", a=A, b=B, dc=DC, v_lp=V_LP, points=2, max_step=0.5)
    for kappa in SLIP_KAPPAS:
        try:
            lo, hi = critical_in_slip("slip", kappa, 0.05, 5.0)
        except ValueError as exc:   # not a bracket: said in the table, not guessed
            out["slip"].append((kappa, math.nan, math.nan, str(exc)))
            continue
        out["slip"].append((kappa, lo, hi, fate_of_perturbation(slip, kappa, lo, max_steps=5_000_000)))
    aging = continue_cycles(state_law="aging", a=A, b=B, dc=DC, v_lp=V_LP, points=2, max_step=0.5)
    for kappa, delta in AGING_RUNS:
        outcome, peak, at = in_slip("aging", kappa, delta, slip_max=500.0)
        out["aging"].append((kappa, delta, outcome, peak, at,
                             fate_of_perturbation(aging, kappa, delta, max_steps=5_000_000)))
    prz = next((r["branch"] for r in results if r["spec"].state_law == "prz" and not r["branch"].spec.inertial
                and r["branch"].meta.get("parameter", "kappa") == "kappa"), None)
    if prz is not None:
        cp = critical_perturbation(prz)
        out["prz"] = [cp[i] for i in range(0, len(cp), max(1, len(cp) // 6))]
    return out


def section(d: Diagram, bautin: dict) -> list:
    """The report's sections (typed blocks, ``report.document``) on the two-parameter diagram, the fold
    curves, the cascade and tori, and the basins."""
    from ...report.document import Figure, Paragraph, Section, Table
    from .report import multiplier_text

    rows = []
    for c in d.curves:
        ks = [p.kappa for p in c.points]
        rows.append([c.state_law, f"{c.eta_bautin:.9g}", f"{len(c.points)}", f"{sum(p.status == 'ok' for p in c.points)}",
                     f"{c.points[0].eta:.4g} … {c.points[-1].eta:.6g}", f"{min(ks):.8f} … {max(ks):.8f}",
                     f"{max(p.residual for p in c.points):.1e}", f"{max(p.fold_residual for p in c.points):.1e}",
                     f"{max(c.period_checks):.1e}", f"fold of \"{c.start}\"", f"{c.seconds:.0f}"])
    blocks = [
        Figure("two-parameter-diagram.png", alt="two-parameter bifurcation diagram"),
        Paragraph(f"Computed in {d.seconds:.0f} s. Planes (η, κ), η = M V_lp²/(a Dc), κ = k/k_c(η). **Hopf curve**: "
                  "κ = 1 by construction; k_c(η) from the eigenvalues alone (secant on Re λ_max, 40 digits, "
                  f"η ∈ {list(HOPF_ETAS)}) lies within {max(d.hopf_dev.values()):.1e} of the closed form for all three "
                  "laws. **Bautin points**: the scan above (l1 = 0). **Fold-of-cycles curves**: one from each Bautin "
                  "point, continued from the fold that the study's subcritical inertial branch of that law flags "
                  "(`two_parameter.fold_curve`: unknowns (w, κ), equations P(w) = w and μ₁ = 1), up to "
                  f"{1 - BAUTIN_GAP:g}·η_B and down to η = {ETA_LOW:g}. Every fold's period is checked by a direct run "
                  "(second turn, an independent step grid). Between two runs of this workflow only the seconds "
                  "changed in this and the following sections."),
        Table(["law", "Bautin η_B", "folds", "converged", "η range", "κ_f range", "max |P(w) − w|", "max |μ₁ − 1|",
               "max |T_direct/T − 1|", "started from", "seconds"], rows)]
    no_curve = [law for law in bautin if not any(c.state_law == law for c in d.curves)]
    if no_curve:
        blocks.append(Paragraph(f"No fold curve for {', '.join(no_curve)}: no Bautin point on the scan (l1 keeps "
                                "its sign), so no fold of cycles is born on the Hopf curve there."))
    for c in d.curves:
        blocks.append(Paragraph(f"{c.state_law}: every 8th fold (Floquet multipliers of the fold's cycle; one is 1):"))
        blocks.append(Table(["η", "κ_f", "period", "ln V max", "ln V min", "multipliers", "|T_direct/T − 1|"],
                            [[f"{p.eta:.6g}", f"{p.kappa:.10f}", f"{p.period:.12g}", f"{p.ln_v_max:.6g}",
                              f"{p.ln_v_min:.6g}", ", ".join(multiplier_text(z, 10) for z in p.multipliers),
                              f"{c.period_checks[j]:.1e}"]
                             for j, p in enumerate(c.points) if j % 8 == 0 or j == len(c.points) - 1]))
    blocks.append(Paragraph("**Regions** are labelled by runs at the marked points: the fate of steady sliding "
                            "perturbed by 1e-2 in ln V (`attractor.fate`), and in the bistable band also the "
                            "coexisting cycle, found by Newton on the return map from outside the fold's cycle:"))
    blocks.append(Table(["law", "η", "κ", "region", "fate of the small perturbation",
                         "coexisting cycle: largest |μ|, ln V span", "as labelled"],
                        [[s.state_law, f"{s.eta:g}", f"{s.kappa:g}", s.region, s.fate,
                          f"{s.cycle_multiplier:.4g}, {s.cycle_span:.4g}" if math.isfinite(s.cycle_multiplier) else "—",
                          "yes" if s.as_labelled else "NO"] for s in d.samples]))
    blocks.append(Paragraph(
        "At η = 0 (quasi-static) the study's runs below k_c blow up (\"Quasi-static fate\" above): runaway. "
        "Above k_c quasi-static, the aging and slip laws have no cycle near the Hopf point (their branches "
        "stay at κ = 1: a neutral family), and PRZ has the unstable cycle whose crossing is the basin boundary "
        "(docs/rate-state.md, \"The basin boundary above k_c\")."))
    out = [Section("Two-parameter bifurcation diagram", blocks)]
    c = d.cascade
    if c is not None:
        rows = []
        for d_, e in zip(c.doublings, c.kappa_errors):
            mult = ", ".join(f"{z.real:.4g}" if abs(z.imag) < 1e-12 else f"{z:.3g}" for z in d_.multipliers_2)
            rows.append([f"{d_.n} → {2 * d_.n}", f"{d_.kappa:.10f}", f"{d_.multiplier:.9f}", f"{e:.1e}",
                         f"{d_.period:.10g}", f"{d_.kappa_2:.10f}, {d_.period_2:.10g}, "
                         f"{d_.period_2 / d_.period:.6f}, {mult}", f"{d_.residual_2:.1e}"])
        blocks = [
            Paragraph("Two slip-law state variables, quasi-static (a = 0.01, b = 0.012, 0.006; Dc = 0.01, 0.1; V_lp = 1; "
                      "supercritical Hopf point): along each branch a real multiplier of Pⁿ crossing −1 is flagged "
                      "by the continuation, located by the secant method on μ_min(κ) + 1, and the period-2n cycle "
                      "through w_PD + ε v (v the eigenvector of −1, ε = 1e-3/2.5^level: the cycles' separation "
                      "shrinks by about that factor per doubling) is switched onto (`doubling.cascade`). "
                      "κ error: max(|μ + 1|, 1e-7) / |dμ/dκ|, the slope from the bracketing branch points and 1e-7 the "
                      "noise of a multiplier from central differences (two runs whose branches started differently "
                      "located the doublings up to 5.4e-11 apart)."),
            Table(["doubling", "κ_PD", "μ at κ_PD", "κ error", "period there",
                   "period-2n cycle: κ, period, period ratio, multipliers", "|P²ⁿ(w) − w|"], rows)]
        if c.ratios:
            rr = ", ".join(f"δ_{i + 1} = {r:.5f} ± {e:.0e}" for i, (r, e) in enumerate(zip(c.ratios, c.ratio_errors)))
            blocks.append(Paragraph(
                f"Ratios of successive intervals (κ_i − κ_(i+1))/(κ_(i+1) − κ_(i+2)): {rr} (the error "
                "propagated from the κ errors). They fall towards a limit, as a Feigenbaum cascade's do; with "
                f"{len(c.ratios)} ratios the limit itself is not pinned down by these data (the differences "
                "between successive ratios are larger than their errors by orders of magnitude, so the "
                "sequence has not converged)."))
        rows = []
        for label, t in d.torus:
            mm = f"{t.max_complex_modulus:.4g}" if math.isfinite(t.max_complex_modulus) else "—"
            rng = (f"{t.modulus_range[0]:.3g} … {t.modulus_range[1]:.3g}" if math.isfinite(t.modulus_range[0])
                   else "— (one multiplier)")
            kinds = " / ".join(", ".join(str(i) for i, k in t.kinds if k == kind) or "—"
                               for kind in ("fold", "period-doubling", "torus"))
            rows.append([label, f"{t.dimension}", f"{len(t.complex_points)}", mm, rng, kinds])
        blocks += [
            Paragraph("**Tori.** A Neimark–Sacker (torus) bifurcation needs a complex pair of multipliers on the unit "
                      "circle. One state variable quasi-static is a planar flow: one multiplier, neither a doubling nor a "
                      "torus. With three state dimensions (one state variable with inertia; two state variables "
                      "quasi-static) there are two multipliers, and a complex pair has modulus √|det ∂P/∂w| = "
                      "exp(½∮ div f dt). Scanned on every branch in κ of the study and the cascade's, with every "
                      "crossing of the unit circle between neighbouring points (`doubling.crossings`: a real "
                      "multiplier through +1 or −1, a complex pair through |μ| = 1; within 1e-6 of the circle on "
                      "both sides is noise):"),
            Table(["branch", "multipliers", "points with a complex pair", "largest |μ| there",
                   "√|det| over the branch", "crossings: fold / doubling / torus (after point)"], rows),
            Paragraph("No torus bifurcation on these branches: where the pair is complex its modulus stays well "
                      "inside the unit circle (the flow contracts area strongly), and where a multiplier leaves the "
                      "circle it is real (a fold or a doubling): the crossings column lists every one.")]
        out.append(Section("Period doubling and tori", blocks))
    if d.basins:
        out.append(_basin_section(d.basins))
    return out


def _basin_section(b: dict):
    from ...report.document import Paragraph, Section, Table

    blocks = [
        Paragraph("The perturbation is a raise Δ of ln θ at V = V_lp (the spring pre-stressed to match: a stress step "
                  "bΔ), the section coordinate of docs/rate-state.md's PRZ basin. A run in time cannot tell a "
                  "blow-up from a transient to V ~ e^50 (both stall near ln V ≈ 30, where the steps fall below the "
                  "resolution of t), so the runaway is decided with slip as the clock (`basin.in_slip`: "
                  "dt/dδ = 1/V, scipy's Radau at rtol 1e-10): \"runs away\" = ln V passes 600; \"returns\" = the "
                  "first spike ends (ln V back below −0.5). The engine's run in time then gives the fate after it."),
        Paragraph("**Slip law** (degenerate Hopf point: no unstable cycle, the branch stays at κ = 1; the boundary is "
                  "not a cycle): Δ_c bracketed by bisection in slip to 1e-3 relative; from the lower end the engine's "
                  "run decays to steady sliding (within 1e-6 in 400 linear periods)."),
        Table(["κ", "Δ_c bracket", "engine fate from the lower end"],
              [[f"{kappa:g}", f"{lo:.5f} … {hi:.5f}", fate] for kappa, lo, hi, fate in b["slip"]]),
        Paragraph("**Aging law**: the same raises return in slip, the spike bounded; the engine's runs decay where "
                  "it can follow the spike (\"undecided\": it stalled near ln V ≈ 30 on a spike that in slip peaks "
                  "higher and ends):"),
        Table(["κ", "Δ", "in slip", "peak ln(V/V_lp)", "at slip δ/Dc", "engine fate"],
              [[f"{kappa:g}", f"{delta:g}", outcome, f"{peak:.4g}", f"{at:.4g}", fate]
               for kappa, delta, outcome, peak, at, fate in b["aging"]]),
        Paragraph("Why the two differ, for V ≫ V_lp (the spike), with slip as the clock and Ω = ln(Vθ/Dc): the "
              "slip law gives exactly dΩ/dδ = [(b − a)Ω/Dc − k]/a, so Ω > κ grows exponentially in slip and "
              "ln V with it — V ~ exp(exp(cδ)) reaches infinity in finite time; the aging law gives "
              "dΩ/dδ = (b − a)[(1 − e^−Ω) − κ]/(a Dc) < 0 for every Ω when κ > 1, so Ω falls, d ln V/dδ "
              "= [b(1 − e^−Ω)/Dc − k]/a ≤ (b/Dc − k)/a, and the spike ends after a slip of at most "
              "~Ω₀ a Dc/((κ − 1)(b − a)): bounded, however large (Δ = 5 at κ = 1.1: e^52.6 above). The slip law's "
              "fast-slip threshold Ω₀ > κ bounds Δ_c from above; the measured Δ_c lie below it (the load-point "
              "term k V_lp/V helps the start)."),
    ]
    if b["prz"]:
        blocks.append(Paragraph("**PRZ**: the boundary is the unstable cycle of the subcritical Hopf point, Δ_c = its crossing "
                  "of V = V_lp minus ln θ* (the study's quasi-static PRZ branch): " +
                  ", ".join(f"{d:.4f} at κ = {k:.6g}" for k, d in b["prz"]) + "."))
    blocks.append(Paragraph("Literature (read through abstracts only): Ranjith & Rice (JMPS 47, 1207, 1999; abstract, SCEC "
              "contribution 561) find for the aging law with the load point moving that \"Slip is always stable "
              "when K > Kcr > 0\", and that \"This is unlike results based on the slip version of the state "
              "evolution law, in which instability occurs in response to sufficiently large perturbations from "
              "steady sliding when K > Kcr\" — what the tables above show. Ciardo & Viesca (arXiv:2407.16846, "
              "abstract) name those slip-law results Gu et al. (1984)'s, quantify critical perturbations for "
              "laws between aging and slip, and find them growing towards the aging law; their numbers, and Gu "
              "et al.'s, could not be read here, so Δ_c is not compared with them number for number."))
    return Section("Basins above k_c (quasi-static): slip law, aging law, PRZ", blocks)
