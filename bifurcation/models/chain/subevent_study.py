"""The presets at their own loading rate, events split in time by a velocity threshold (issue 17).

At the presets' ν = 0.01 a long chain is never all stuck, so the all-stuck events of the report's
preset section never end there (that section runs ν = 1e-5). Here the catalog is cut by V_th
(``_subevents``: an event lasts while some block is faster than V_th). One run per preset, in chunks
with a progress line each, until the event target or the CPU budget; the statistics go to
``subevents_<label>.json`` and ``report`` writes ``PUBLISHED_NU.md`` from those files alone (so
rewriting the page rewrites nothing else).

    python -m bifurcation.models.chain.subevent_study run carlson-langer-1991 --events 1000000 --cpu 1500 --out results/chain
    python -m bifurcation.models.chain.subevent_study run mori-kawamura-2006 --nu-f 0.5 --events 1000000 --cpu 1500 --out results/chain
    python -m bifurcation.models.chain.subevent_study report results/chain
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

__all__ = ["DEFAULT_V_THRESHOLD", "main", "published_nu_jobs", "run_preset", "write_report"]

#: V_th of these runs: J. Xia's velocity cutoff v_0 = 1e-4 (physics.clarku.edu/~jcxia/EQProject/BK1D.html,
#: the "cutoff v_0" table, 1e-4 and 1e-5, in a model driven at ν = 0 during events). It is below a lone
#: block's largest velocity at these presets (1.04e-3 for carlson-langer-1991, docs/chain.md) and below ν.
DEFAULT_V_THRESHOLD = 1e-4


def run_preset(name, *, nu_f=None, events=10**6, cpu=1500.0, v_threshold=DEFAULT_V_THRESHOLD, seed=1,
               amplitude=0.1, chunk=5000, transient_cycles=1.0, bootstrap=100, echo=print) -> dict:
    from ...laws import resolve_law
    from ._subevents import SubeventRun
    from ._validate import check_initial
    from .clauset import clauset_fit
    from .presets import get_preset

    p = get_preset(name)
    nu_f = p.nu_f if nu_f is None else float(nu_f)
    u = check_initial(p.n, p.ell, p.ends, None, amplitude, seed)
    r = SubeventRun(resolve_law(p.law), p.n, p.ell, p.nu, nu_f, p.ends, u, v_threshold=v_threshold, sigma=p.sigma)
    parts, done, c0, status = [], 0, time.process_time(), "complete"
    while done < events:
        out = r.run(min(chunk, events - done), t_stop=r.t + 10.0 / p.nu)    # ≤ 10 loading cycles per call
        parts.append(out["catalog"])
        done += out["catalog"]["potency"].size
        cpu_used = time.process_time() - c0
        echo(f"{name} ν_f = {nu_f:g}: {done} events, t = {r.t:.6g}, "
             f"{cpu_used:.0f} CPU s, widest window {int(r.totals[4])}", flush=True)
        if str(out["status"]) != "complete":
            status = f"{out['status']}: {out['message']}"
            break
        if cpu_used > cpu:
            status = f"CPU budget of {cpu:g} s reached"
            break
    cpu_run = time.process_time() - c0
    cat = {k: np.concatenate([q[k] for q in parts]) for k in parts[0]}
    t, pot, nb, dur = cat["t_start"], cat["potency"], cat["n_blocks"], cat["duration"]
    cycles = p.nu * (t - t[0]) if t.size else t
    keep = cycles >= transient_cycles
    pot, nb, dur = pot[keep], nb[keep], dur[keep]
    n = p.n
    res = {"preset": name, "law": p.law, "n": n, "ell": p.ell, "nu": p.nu, "nu_f": nu_f, "sigma": p.sigma,
           "ends": p.ends, "v_threshold": v_threshold, "membership": f"v-threshold={v_threshold!r}, split in time",
           "seed": seed, "amplitude": amplitude, "events": int(t.size), "kept": int(keep.sum()),
           "transient_cycles": transient_cycles, "status": status, "cpu_run": cpu_run,
           "cpu_per_event": cpu_run / max(1, t.size), "loading_cycles": float(cycles[-1]) if t.size else 0.0,
           "stretches_ended": int(r.totals[0]), "slip_below": float(r.totals[1]), "slip_in_events": float(r.totals[2]),
           "widest_window": int(r.totals[4]), "steps": int(r.totals[3])}
    res["n_blocks"] = {"mean": float(nb.mean()), "max": int(nb.max()), "one": int((nb == 1).sum()),
                       "large": int((nb >= n // 2).sum()), "spanning": int((nb == n).sum())}
    res["duration"] = {"mean": float(dur.mean()), "max": float(dur.max()),
                       "over_one_cycle": int((dur * p.nu >= 1.0).sum())}
    m = np.log10(pot[pot > 0])
    edges = np.arange(math.floor(m.min() * 10) / 10, m.max() + 0.2, 0.1)
    counts, _ = np.histogram(m, edges)
    res["mfd"] = {"edges": edges.tolist(), "counts": counts.tolist()}
    c1 = time.process_time()
    f = clauset_fit(pot, bootstrap=bootstrap, block_bootstrap=100, seed=1, resolution=10)
    res["fit"] = {"n": f.n, "n_tail": f.n_tail, "xmin": f.xmin, "alpha": f.alpha, "alpha_err": f.alpha_err,
                  "alpha_block_err": f.alpha_block_err, "block": f.block, "ks": f.ks, "p": f.p_value,
                  "bootstrap": f.bootstrap, "ratios": {k: list(v) for k, v in f.ratios.items()},
                  "b_P": f.b_potency, "b_M": f.b_magnitude, "largest": float(pot.max())}
    large = nb >= max(2, n // 2)
    if large.any() and pot[large].min() >= f.xmin:
        p_l = float(pot[large].min())
        exp = f.n_tail * (p_l / f.xmin) ** (1 - f.alpha)
        res["excess"] = {"large": int(large.sum()), "p_large": p_l, "observed": int((pot >= p_l).sum()), "expected": exp}
    else:
        res["excess"] = {"large": int(large.sum())}
    res["cpu_stats"] = time.process_time() - c1
    return res


def published_nu_jobs(cfg) -> list:
    """The workflow's ``[published_nu]`` runs as (function, argument, cost) jobs of the study's pool
    (``study.py --published-nu-only``); each job returns run_preset's dict with its ``run_cfg``."""
    p = cfg.get("published_nu")
    if not p:
        return []
    shared = {k: v for k, v in p.items() if k != "run"}
    return [(_published_job, (shared, dict(run)), float(p.get("cpu", 600.0))) for run in p["run"]]


def _published_job(args) -> dict:
    shared, run = args
    res = run_preset(run["preset"], nu_f=run.get("nu_f"), events=int(shared.get("events", 10**6)),
                     cpu=float(shared.get("cpu", 600.0)), v_threshold=float(shared.get("v_threshold", 0.1)),
                     transient_cycles=float(shared.get("transient_cycles", 1.0)),
                     bootstrap=int(shared.get("bootstrap", 100)))
    res["run_cfg"] = dict(shared, **run)
    return res


def write_json(res, folder) -> Path:
    """``subevents_<preset>_nuf<ν_f>_vth<V_th>.json`` in ``folder`` (what ``report`` and the study read)."""
    out = Path(folder) / f"subevents_{_label(res)}.json"
    out.write_text(json.dumps(res, indent=1))
    return out


def _label(res) -> str:
    return f"{res['preset']}_nuf{res['nu_f']:g}_vth{res['v_threshold']:g}"


def _reading(f) -> str:
    """The fit's word by the page's rule: no scaling range, ruled out, undecided, plausible; with the alternatives
    the likelihood ratios favour (R < 0, p < 0.1)."""
    from .clauset import p_reading

    word = ("no scaling range" if math.log10(f["largest"] / f["xmin"]) < 1
            else "power law " + p_reading(f["p"], f["bootstrap"]))
    fav = [k.replace("_", " ") for k, (r, q) in f["ratios"].items() if r < 0 and q < 0.1]
    return f"**{word}**" + (f"; favoured: {', '.join(fav)}" if fav else "")


def write_report(folder) -> Path:
    """PUBLISHED_NU.md from the subevents_*.json of ``folder`` (nothing else read or written)."""
    from .clauset import p_upper

    folder = Path(folder)
    rows = [json.loads(q.read_text()) for q in sorted(folder.glob("subevents_*.json"))]
    lines = ["# Presets at their own ν = 0.01: events split in time by a velocity threshold", "",
             "Produced by `bifurcation study chain workflows/chain-report.toml --out " + str(folder) + " --published-nu-only` "
             "(its `[published_nu]` table: one catalog per `[[published_nu.run]]`, each one process bounded by the "
             "table's `cpu`; then `python -m bifurcation.models.chain.subevent_study report " + str(folder) + "` "
             "rewrites this page alone) from the `subevents_*.json` beside it. Engine: the compiled chain engine with "
             "the velocity-threshold root (`_subevents.py`, docs/chain.md \"Event membership\"): an event opens when "
             "some block's velocity exceeds V_th and closes when none does; its potency is all slip in that interval, "
             "n_blocks the blocks above V_th in it. Slip while no block exceeds V_th is counted apart (column 'slip "
             "below V_th'). Random start of amplitude 0.1 (seed 1); events of the first loading cycle dropped. Chaotic "
             "sequences: digits of single events, and the number of events a CPU budget reaches, depend on the CPU "
             "and its load; the statistics within their errors do not."
             + (" Records without the workflow's `run_cfg` (" + ", ".join(f"`{_label(r)}`" for r in rows if "run_cfg" not in r)
                + ") were written by `python -m bifurcation.models.chain.subevent_study run PRESET [--nu-f X] --cpu 100 "
                "--v-threshold 0.1 --bootstrap 100` before the workflow table existed: the same function and arguments "
                "as the table's." if any("run_cfg" not in r for r in rows) else ""), "",
             "Fits: Clauset–Shalizi–Newman through `powerlaw` (`clauset.clauset_fit`, x_min on a grid of 10 data "
             "values per decade). p from B parametric bootstrap samples (each with its own x_min search): "
             "resolution ±√(p(1 − p)/B); k of B samples at least as far from their fit as the data bound p by the "
             "one-sided 95 % Clopper–Pearson limit (0.030 for 0 of 100). Reading (`clauset.p_reading`): **ruled out** "
             "when that bound is ≤ 0.1, **plausible** when p > 0.1, **undecided** otherwise; **no scaling range** when "
             "the tail spans < 1 decade (largest P / x_min < 10), whatever p. Clauset's 2500 samples (±0.01) cost 25× "
             "the CPU of B = 100 and were not run. The error of α is a moving-block bootstrap (100 resamples of "
             "blocks of ⌈n^(1/3)⌉ events, serial correlation); the goodness-of-fit bootstrap itself resamples "
             "independently. b_P = α − 1 (potency), b_M = 1.5 (α − 1) (moment magnitude). "
             "KS (powerlaw's D): `powerlaw`'s KS distance, whose empirical CDF is (i − 1)/n at the i-th smallest "
             "size, one side of each step (powerlaw-devs/powerlaw issue #111); the two-sided supremum lies between D "
             "and D + 1/n_tail (the bound given), and is not given itself because the catalogs are not kept; the "
             "bootstrap p compares like with like.", "",
             "| preset (ν_f, α = 1/(2ν_f)) | N, ℓ, ν, σ, ends | V_th | events (kept), status | loading cycles | CPU s per "
             "event (run + stats; 10^6 events at that rate) | all-stuck stretches ended | slip below V_th / in events | n_blocks mean / max, ≥ N/2 "
             "| duration mean / max (events over 1 cycle) | CSN fit | reading | excess ≥ N/2 |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        f = r["fit"]
        lr = ", ".join(f"{k} R = {v[0]:+.1f} (p = {v[1]:.2g})" for k, v in f["ratios"].items())
        ex = r["excess"]
        exs = (f"{ex['observed']} with P ≥ {ex['p_large']:.3g} against {ex['expected']:.3g} predicted"
               if "expected" in ex else f"{ex['large']} events ≥ N/2" + (", below x_min: undecided" if ex["large"] else ""))
        lines.append(
            f"| `{r['preset']}` ({r['nu_f']:g}, {0.5 / r['nu_f']:g}) | {r['n']}, {r['ell']:g}, {r['nu']:g}, {r['sigma']:g}, "
            f"{r['ends']} | {r['v_threshold']:g} | {r['events']} ({r['kept']}), {r['status']} | {r['loading_cycles']:.1f} | "
            f"{r['cpu_per_event'] * 1e3:.3g} ms ({r['cpu_run']:.0f} + {r['cpu_stats']:.0f} s; 10^6 events: "
            f"{r['cpu_per_event'] * 1e6 / 3600:.0f} CPU h) | {r['stretches_ended']} | "
            f"{r['slip_below']:.3g} / {r['slip_in_events']:.4g} | {r['n_blocks']['mean']:.2f} / {r['n_blocks']['max']}, "
            f"{r['n_blocks']['large']} | {r['duration']['mean']:.3g} / {r['duration']['max']:.3g} "
            f"({r['duration']['over_one_cycle']}) | α = {f['alpha']:.3f} ± {f['alpha_block_err']:.3f} above x_min = "
            f"{f['xmin']:.3g} ({f['n_tail']} of {f['n']}; largest P {f['largest']:.3g}); b_P = {f['b_P']:.3f}, "
            f"b_M = {f['b_M']:.3f}; KS (powerlaw's D) {f['ks']:.4f}, two-sided ≤ "
            f"{math.ceil((f['ks'] + 1 / f['n_tail']) * 1e4) / 1e4:.4f}; p = {f['p']:.2f} ({round(f['p'] * f['bootstrap'])} of "
            f"B = {f['bootstrap']}, ≤ {p_upper(f['p'], f['bootstrap']):.2g} at 95 %); LR: {lr} | {_reading(f)} | {exs} |")
    lines += ["", "LR: normalised log-likelihood ratio R of the power law against each alternative (R > 0 favours the "
              "power law) with its p. Published numbers beside these: none could be read (presets.py says which "
              "numbers of each preset were read and where; MK's and CLST's texts were not found).", ""]
    out = folder / "PUBLISHED_NU.md"
    out.write_text("\n".join(lines))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m bifurcation.models.chain.subevent_study")
    sub = ap.add_subparsers(dest="cmd", required=True)
    a = sub.add_parser("run")
    a.add_argument("preset")
    a.add_argument("--nu-f", type=float, default=None)
    a.add_argument("--events", type=int, default=10**6)
    a.add_argument("--cpu", type=float, default=1500.0)
    a.add_argument("--v-threshold", type=float, default=DEFAULT_V_THRESHOLD)
    a.add_argument("--bootstrap", type=int, default=100)
    a.add_argument("--out", required=True)
    b = sub.add_parser("report")
    b.add_argument("folder")
    args = ap.parse_args(argv)
    if args.cmd == "report":
        if not Path(args.folder).is_dir():
            print(f"error: folder={args.folder!r}: is not a directory; give the folder of the subevents_*.json "
                  "files, such as results/chain", file=sys.stderr)
            return 2
        print(write_report(args.folder))
        return 0
    from .presets import get_preset
    from ...errors import InputError
    try:
        get_preset(args.preset)
        for name, value, ok, fix in (
                ("--events", args.events, args.events >= 1, "give a count ≥ 1"),
                ("--cpu", args.cpu, math.isfinite(args.cpu) and args.cpu > 0, "give CPU seconds > 0"),
                ("--v-threshold", args.v_threshold, math.isfinite(args.v_threshold) and args.v_threshold > 0,
                 "give a slip velocity > 0, such as 0.1"),
                ("--bootstrap", args.bootstrap, args.bootstrap >= 0, "give a count ≥ 0"),
                ("--nu-f", args.nu_f, args.nu_f is None or (math.isfinite(args.nu_f) and args.nu_f > 0),
                 "give ν_f > 0"),
                ("--out", args.out, Path(args.out).is_dir(), "give an existing directory")):
            if not ok:
                raise InputError(name, value, "is not accepted", fix)
    except InputError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    res = run_preset(args.preset, nu_f=args.nu_f, events=args.events, cpu=args.cpu, v_threshold=args.v_threshold,
                     bootstrap=args.bootstrap)
    print(write_json(res, args.out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
