"""The chain report's magnitude–frequency study near the uniform mode's ν_f = 1/2 (``[near_half]`` of the
workflow): budgeted catalogs per (ν, ν_f, N), their cutoff and spanning statistics, finite-size fits,
the reading (``scaling.mfd_reading``) and its figure; the small-ν sweeps (``[sweep_small_nu]``).
Text: ``_study_mfd_text``.
"""

from __future__ import annotations

import math
import time

import numpy as np

from .analysis import finite_size_fit
from .scaling import mfd_reading, moment_cutoff, slip_clusters, tapered_gr

__all__ = ["near_half_figure", "near_half_jobs", "near_half_stats", "small_nu_jobs"]


def _budgeted_catalog(args) -> dict:
    """One catalog from the seeded random start: events after ``transient`` loading cycles are
    kept until ``events`` are kept, the driver has covered ``cycles`` loading cycles after the
    transient, ``cpu`` CPU seconds are spent, or one event lasts longer than ``longest_event`` cycles
    (t_max of the event; the unfinished event is not catalogued). ``cut`` says which bound stopped it.
    Per kept event also its connected slip patches (``scaling.slip_clusters`` of U(end) − U(start)):
    ``c_size``, ``c_potency`` and ``c_event`` (the index of their event)."""
    from ...laws import resolve_law
    from ...run.progress import event_lines
    from ._loop import ChainLoop
    from ._validate import check_initial

    c, nh, nu, nu_f, n, cycles, transient = args
    t0, c0 = time.perf_counter(), time.process_time()
    u0 = check_initial(n, c["ell"], c["ends"], None, c["amplitude"], nh["seed"])
    loop = ChainLoop(resolve_law(c["law"]), n, c["ell"], nu, nu_f, c["ends"], u0, t_max=nh["longest_event"] / nu)
    keys = ("t_start", "potency", "n_blocks", "hypocentre", "duration")
    cat = {k: [] for k in (*keys, "c_size", "c_potency", "c_event")}
    t_first, cut, message = None, "events", ""
    line = event_lines(f"study chain: near ν_f = 1/2, N = {n}, ν = {nu:g}, ν_f = {nu_f:g}")
    while len(cat["potency"]) < nh["events"]:
        line(len(cat["potency"]), nh["events"], float(loop.t))
        if time.process_time() - c0 > nh["cpu"]:
            cut = "cpu"
            break
        u = loop.u.copy()
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
        size, pot = slip_clusters(loop.u - u, c["ends"] == "periodic")
        cat["c_size"] += size.tolist()
        cat["c_potency"] += pot.tolist()
        cat["c_event"] += [len(cat["potency"]) - 1] * size.size
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


def _row(r, csn=None) -> dict:
    """Statistics of one budgeted catalog (docs/chain.md, "Cutoff and finite-size scaling"); ``csn``: a
    ``_study_csn.CsnCache`` for the Clauset–Shalizi–Newman fit of the multi-block sizes (None: not fitted)."""
    from .study import _catalog_stats

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
               tapered=tapered_gr(p[multi], p_min), csn=csn.fit(p[multi]) if csn is not None else None, moments=moment_cutoff(p), moments_multi=moment_cutoff(p[multi]),
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


def _patches(r) -> dict:
    """The catalog of connected slip patches in place of the events (each with its event's time)."""
    ev = np.array(r["c_event"], dtype=int)
    return dict(r, potency=list(r["c_potency"]), n_blocks=list(r["c_size"]),
                t_start=np.array(r["t_start"])[ev].tolist(), duration=np.array(r["duration"])[ev].tolist(),
                hypocentre=[0] * ev.size)


def _groups(rows, merged_rule: bool) -> list:
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
                                "csn": r.get("csn"),
                                **({"slip_fraction": r["slip_fraction"]} if merged_rule else {})} for r in rs],
                              fss["cutoff"], fss["span"])
        groups.append({"nu": nu, "nu_f": nf, "sizes": [r["n"] for r in rs], "fss": fss, "reading": list(reading)})
    return groups


def near_half_stats(results, cfg, csn=None) -> dict:
    """Rows per catalog and, per (ν, ν_f), finite-size fits over N of the cutoff ⟨P²⟩/⟨P⟩, the mean
    potency and the spanning fraction, and the reading (scaling.mfd_reading); ``csn`` as ``_row``."""
    key = lambda d: (-d["nu"], d["nu_f"], d["n"])  # noqa: E731
    rows = sorted((_row(r, csn) for r in results), key=key)
    patches = sorted((_row(_patches(r), csn) for r in results if "c_event" in r), key=key)
    return {"rows": rows, "groups": _groups(rows, True), "patch_rows": patches, "patch_groups": _groups(patches, False)}


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
    fig.savefig(out / "fig_mfd_half.png", dpi=110, metadata={"Software": None})
    plt.close(fig)


def _sweep_small_nu(args) -> dict:
    """A sweep of ``[sweep_small_nu]``: the main sweep's runner (``report._sweep``) at another ν."""
    from .study import _sweep

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
