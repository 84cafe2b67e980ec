"""The rate-state study's store (``branches.RATE_STATE_BRANCHES``), bifurcation diagram and report (REPORT.md,
report.html; see study.py)."""

from __future__ import annotations

import math
import platform

import numpy as np

__all__ = ["multiplier_text", "stick_slip_text", "verdict", "write_report", "write_store"]


#: Floquet multipliers come from central differences of the return map (h = 1e-5), where truncation and
#: rounding balance near 1e-10 (docs/rate-state.md, "Two-parameter continuation"): a smaller |μ| has no
#: significant digit, and its printed digits changed between runs, so it is shown as this bound.
MULTIPLIER_NOISE = 1e-9


def multiplier_text(value: float, digits: int = 6) -> str:
    """|μ| to ``digits`` significant digits, or "< 1e-9" where it is below the finite-difference noise."""
    value = abs(value)
    return f"< {MULTIPLIER_NOISE:.0e}".replace("e-0", "e-") if value < MULTIPLIER_NOISE else f"{value:.{digits}g}"


def _amplitude(p) -> float:
    return p.ln_v_max - p.ln_v_min


def _stable(p) -> bool:
    """Strictly stable: every nontrivial multiplier inside the unit circle by more than FD noise (1e-6).

    On the degenerate families (quasi-static aging and slip at k_c) the multiplier is 1 to ~1e-8:
    neutral, drawn dashed with the unstable ones.
    """
    return max(abs(z) for z in p.multipliers) < 1 - 1e-6


#: a run stopped (stalled or unbounded) at ln(V/V_lp) above this is a blow-up (attractor.fate's rule; the
#: quasi-static runs below k_c stall at ln V ≈ 22-30, where the step falls below the resolution of t)
BLOWUP_LN_V = 10.0


def blew_up(fate: dict) -> bool:
    """Whether a quasi-static fate row is a blow-up: unbounded, or stopped early at large V."""
    return fate["status"] == "unbounded" or (fate["status"] != "ok" and fate.get("ln_v_stop", math.nan) > BLOWUP_LN_V)


def verdict(result: dict, fates: list) -> dict:
    """Criticality, fold, amplitude at k_c on the stable branch, and the order of the transition."""
    branch = result["branch"]
    h = branch.hopf
    pts = branch.points
    fold = pts[branch.folds[0]].kappa if branch.folds else math.nan
    jump = math.nan
    stable = [p for p in pts if _stable(p) and p.kappa <= 1.0 + 1e-9]
    upper = [p for p in pts if _stable(p) and _amplitude(p) > 10 * _amplitude(pts[0])]
    if h.criticality == "subcritical" and branch.folds and upper:
        # The stable large cycles that the system jumps to when steady sliding loses stability at κ = 1.
        ks = np.array([p.kappa for p in upper])
        amps = np.array([_amplitude(p) for p in upper])
        order = np.argsort(ks)
        if ks.min() <= 1 <= ks.max():
            jump = float(np.interp(1.0, ks[order], amps[order]))
    inertial = branch.spec.inertial
    if h.criticality == "supercritical":
        order = "continuous (second order): stable cycles grow from zero amplitude below k_c"
    elif not inertial:
        fate = [f for f in fates if f["state_law"] == branch.spec.state_law[0]]
        blown = bool(fate) and all(blew_up(f) for f in fate if f["kappa"] == 0.9)
        order = ("first order: no bounded cycle below k_c, V blows up (quasi-static)" if blown
                 else "first order (no stable small cycle below k_c)")
        if h.criticality == "degenerate":
            order = "degenerate at k_c (a family of cycles), " + order
    elif not math.isnan(jump):
        order = f"first order: jump to Δln V = {jump:.3g} at k_c, hysteresis up to κ = {fold:.6g}"
    else:
        order = "first order (subcritical), stable branch not reached"
    return {"criticality": h.criticality, "fold_kappa": fold, "jump": jump, "order": order,
            "stable_points": len(stable)}


def write_store(path, spec, results) -> None:
    """The study's store at ``path``, written through ``bifurcation.store`` (``branches.write_branch_store``)."""
    from .branches import write_branch_store

    write_branch_store(path, spec, results)


def _figure(path, results) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    drawn = [r for r in results if r["branch"].meta.get("parameter", "kappa") == "kappa"]  # V_lp: own table
    panels = [(False, "quasi-static"), (True, "inertial (η = M V²/(a Dc))")]
    panels = [p for p in panels if any(r["branch"].spec.inertial == p[0] for r in drawn)] or panels[:1]
    fig, axes = plt.subplots(1, len(panels), figsize=(5.5 * len(panels), 4.2), sharey=True, squeeze=False)
    axes = axes[0]
    column = {inertial: i for i, (inertial, _) in enumerate(panels)}
    for r in drawn:
        b = r["branch"]
        ax = axes[column[b.spec.inertial]]
        k = np.array([p.kappa for p in b.points])
        amp = np.array([_amplitude(p) for p in b.points])
        st = np.array([_stable(p) for p in b.points])
        line, = ax.plot(k, amp, lw=0.8, alpha=0.4)
        ax.plot(np.where(st, k, np.nan), np.where(st, amp, np.nan), "-", color=line.get_color(), lw=2,
                label=f"{r['spec'].label} ({b.hopf.criticality})")
        ax.plot(np.where(~st, k, np.nan), np.where(~st, amp, np.nan), "--", color=line.get_color(), lw=1.5)
        for i in b.folds:
            ax.plot(b.points[i].kappa, _amplitude(b.points[i]), "o", color=line.get_color())
    for ax, (_, title) in zip(axes, panels):
        ax.axvline(1.0, color="k", lw=0.5)
        ax.set_yscale("log")
        ax.set_xlabel("κ = k / k_c")
        ax.set_title(title)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
    axes[0].set_ylabel("cycle amplitude ln V_max − ln V_min")
    fig.suptitle("Cycles born at the Hopf point (solid: stable, dashed: unstable or neutral, dots: folds)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110, metadata={"Software": None})   # the same bytes for the same drawing
    plt.close(fig)


def stick_slip_text(results) -> str:
    """The report's paragraph on stick-slip-like cycles, with the deepest point and the widest cycle of the
    branches in κ named: "10 decades below V_lp" (ln(V_min/V_lp) < −23) and "10 decades over a cycle"
    (ln(V_max/V_min) > 23) are different measures, and a neutral quasi-static family can pass the second
    without the first."""
    deep = min(((p.ln_v_min - math.log(r["branch"].v_lp), r["spec"].label) for r in results
                for p in r["branch"].points), default=(math.nan, "—"))
    wide = max(((p.ln_v_max - p.ln_v_min, r["spec"].label) for r in results for p in r["branch"].points),
               default=(math.nan, "—"))
    return ("Stick-slip-like cycles, V falling more than 10 decades below V_lp (ln(V_min/V_lp) < −23), are not "
            f"reached on these branches (lowest ln(V_min/V_lp): {deep[0]:.4g}, {deep[1]}; the widest cycle spans "
            f"{wide[0]:.4g} in ln V over a cycle, {wide[1]}): on the quasi-static ones V blows up first; on the "
            "inertial ones the fast mode of ln V relaxes at a rate a/(M V), and below ln V ≈ −9 the explicit "
            "Taylor steps reach its stability limit (the continuation stops there with its reason, see `stop`). "
            "With b/a = 5 and η = 100 the slip law's attracting cycles pass 10 decades over a cycle "
            "(ln(V_max/V_min) > 23 for κ < 0.044), with V_min then 9.7 decades below V_lp (docs/rate-state.md, "
            "\"Where cycles become stick-slip-like\").")


def write_report(out, spec, sweep, bautin, results, fates, seconds, workflow="workflows/rate-state.toml",
                 diagram=None) -> None:
    """``REPORT.md``, ``report.html`` (the same typed blocks, ``report.document``) and the bifurcation diagram."""
    from ...report.document import Figure, Heading, Paragraph, Section, Table, to_html, to_markdown

    _figure(out / "bifurcation-diagram.png", results)
    extra = []
    if diagram is not None:   # the two-parameter diagram (diagram.py): its figure and section
        from .diagram import figure, section

        figure(out / "two-parameter-diagram.png", results, bautin, diagram.curves, diagram.samples, fates,
               diagram.cascade)
        extra = section(diagram, bautin)
    in_v = [r for r in results if r["branch"].meta.get("parameter", "kappa") == "v_lp"]
    results = [r for r in results if r not in in_v]
    rows = []
    for r in results:
        v = verdict(r, fates)
        b = r["branch"]
        fold = f"{v['fold_kappa']:.6g}" if not math.isnan(v["fold_kappa"]) else "—"
        rows.append([r["spec"].label, f"{b.hopf.lyapunov_coefficient:.4g}", f"{r['l1_simulation']:.4g}",
                     v["criticality"], fold, v["order"]])
    bl = ", ".join(f"{law}: {('η = %.6g' % e) if not math.isnan(e) else 'none in [1e-3, 3]'}"
                   for law, e in bautin.items())
    bl = (f"Bautin points (l1 changes sign with inertia; subcritical below, supercritical above): {bl}."
          if bautin else "Bautin points: not searched (the workflow sets `[hopf] bautin = false`).")
    verdicts = Section("The verdict: is the loss of stick-slip first order?", [
        Table(["branch", "l1 (normal form)", "l1 (direct simulation, ε = 5e-3)", "criticality", "fold κ", "verdict"],
              rows),
        Paragraph("Quasi-static fate below k_c (start 1 % off steady state, 400 linear periods; a run stopped "
                  f"at ln V > {BLOWUP_LN_V:g}, the step having fallen below the resolution of t, is counted as a "
                  "blow-up by the verdict, which reads the κ = 0.9 rows. A stop cannot tell a blow-up from a large "
                  "spike that returns (see the basins section); tests/test_rate_state_fates_in_slip.py follows "
                  "these runs with slip as the clock: which rows run away there, and which stop on a spike that "
                  "returns, is said in docs/rate-state.md, \"Quasi-static fate below k_c\"):"),
        Table(["law", "κ", "status", "largest completed maximum of ln V", "ln V where the run stopped"],
              [[f["state_law"], f"{f['kappa']}", f["status"], f"{f['ln_v_max']:.3g}",
                f"{f.get('ln_v_stop', math.nan):.3g}"] for f in fates]),
        Paragraph(bl),
        Figure("bifurcation-diagram.png", alt="bifurcation diagram")])
    hopf = Section("Hopf point: numerical vs closed forms", [
        Paragraph("k_c found from the eigenvalues alone (mpmath, 30 digits; deviations at that precision, before "
                  "rounding to double — as doubles both are the same number) against k_c = (b − a)/Dc·[1 + M V²/(a "
                  "Dc)] and ω_c = (V/Dc)√((b − a)/a); b/a ∈ "
                  f"{list(spec.hopf_b_over_a)}, V_lp ∈ {list(spec.hopf_v_lp)}, η ∈ {list(spec.hopf_eta)}."),
        Table(["law", "η", "cases", "max rel. dev. k_c", "max rel. dev. ω_c"],
              [[s["state_law"], f"{s['eta']:g}", f"{s['cases']}", f"{s['max_rel_dev_k_c']:.1e}",
                f"{s['max_rel_dev_omega_c']:.1e}"] for s in sweep])])
    rows = []
    for r in results:
        b = r["branch"]
        ks = [p.kappa for p in b.points]
        ts = [p.period for p in b.points]
        mm = max(max(abs(z) for z in p.multipliers) for p in b.points)
        q = max(r["period_check_quad"].values()) if r["period_check_quad"] else math.nan
        rows.append([r["spec"].label, f"{len(b.points)}", f"{min(ks):.6g} … {max(ks):.6g}",
                     f"{min(ts):.6g} … {max(ts):.6g}", f"{max(r['period_check']):.1e}", f"{q:.1e}", f"{mm:.4g}",
                     f"{b.meta['stop']}", f"{r['seconds']:.0f}"])
    branches = [Table(["branch", "points", "κ range", "period range",
                       "max |T_direct/T − 1| (double 2nd turn; quad where |multiplier| > 10)",
                       "max (quad, every 10th + folds)", "largest |multiplier|", "stop", "seconds"], rows)]
    for r in (r for r in results if r["branch"].folds):
        b = r["branch"]
        i = b.folds[0]
        rows = []
        for j, p in enumerate(b.points):
            if j % 5 == 0 or abs(j - i) <= 2 or j == len(b.points) - 1:
                rows.append([f"{j}{' (fold)' if j == i else ''}", f"{p.kappa:.10g}", f"{p.period:.12g}",
                             f"{p.ln_v_max:.5g}", f"{p.ln_v_min:.5g}", f"{p.slip:.6g}",
                             ", ".join(multiplier_text(z) for z in p.multipliers), f"{r['period_check'][j]:.1e}"])
        branches.append(Section(f"{r['spec'].label}: through the fold", [
            Table(["point", "κ", "period", "ln V max", "ln V min", "slip/cycle", "Floquet multipliers",
                   "|T_direct/T − 1|"], rows)], level=3))
    for r in in_v:
        b = r["branch"]
        branches.append(Section(f"{r['spec'].label}: a branch in V_lp at fixed k = {b.meta['k']:.10g}", [
            Paragraph(f"From the cycle at V_lp = {b.v_lp:g} of the branch in κ; {b.meta['stop']}. κ = k/k_c(V_lp) "
                      "with the closed-form k_c. Quasi-static, V_lp only rescales the cycle (V_lp·T and ln(V/V_lp) "
                      "constant); with inertia k_c grows like 1 + M V_lp²/(a Dc), so a faster load point is a "
                      "softer spring."),
            Table(["point", "V_lp", "κ", "period T", "V_lp·T", "ln(V_max/V_lp)", "ln(V_min/V_lp)",
                   "largest |multiplier|", "|T_direct/T − 1|"],
                  [[f"{j}", f"{p.v_lp:.6g}", f"{p.kappa:.8g}", f"{p.period:.12g}", f"{p.v_lp * p.period:.12g}",
                    f"{p.ln_v_max - math.log(p.v_lp):.10g}", f"{p.ln_v_min - math.log(p.v_lp):.10g}",
                    f"{max(abs(z) for z in p.multipliers):.6g}", f"{r['period_check'][j]:.1e}"]
                   for j, p in enumerate(b.points)])], level=3))
    branches.append(Paragraph(stick_slip_text(results)))
    blocks = [
        Heading(f"Rate-and-state spring-slider: Hopf bifurcation and cycles ({spec.name})", 1),
        Paragraph(f"Produced by `bifurcation continue {workflow}` in {seconds:.0f} s on {platform.machine()} (one "
                  "process). Model and equations: docs/rate-state.md.\n"
                  "Slider a = 0.01, b = 0.015, Dc = 0.01, V_lp = 1 unless stated; η = M V_lp²/(a Dc); κ = k/k_c."),
        Paragraph("Numbers that change between runs and CPUs (heyoka compiles for the host; the load sets the "
                  "times), and only these changed between two runs of this workflow: the seconds; the simulated "
                  "l1 of the degenerate branches (~1e-12: rounding, not a coefficient); the period checks "
                  "|T_direct/T − 1| (rounding, ≤ 1e-11); Floquet multipliers below ~1e-9 (finite-difference "
                  "noise of the trivial direction, now printed as < 1e-9). Every other printed digit was the same. "
                  "The store branches.zarr beside this report holds the branches (the tables of the Branches section "
                  "and the verdict's l1 from the normal form, criticality and fold κ); every other number here "
                  "(the Hopf sweep, l1 by direct simulation, the quasi-static fates, the Bautin points, the "
                  "two-parameter diagram, the cascade, the tori and the basins) is computed by the same run and "
                  "written only into this report, with no data file beside it; docs/rate-state.md names the tests "
                  "that check the methods behind them."),
        verdicts, hopf, Section("Branches", branches), *extra]
    (out / "REPORT.md").write_text(to_markdown(blocks), encoding="utf-8")
    (out / "report.html").write_text(to_html(blocks, out), encoding="utf-8")
