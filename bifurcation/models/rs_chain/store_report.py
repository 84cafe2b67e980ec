"""The rate-and-state chain's section of ``bifurcation report --store``: its runs and their catalogs.

Per run (at most ``MAX_RUNS`` rows): the parameters that vary across the store, the status, the
events catalogued, the mean potency, the largest event (blocks), the share of system-spanning events
(n_blocks = N) and the largest stress-balance residual of its events (``balance_max``). Catalogs are
read through the store's public reader ``bifurcation.store.catalog.open_catalog``.

With an output directory, for up to ``MAX_DRAWN`` runs (evenly spread over the runs with events):

* **event sizes**: the potency P of each event after the transient (the first ``TRANSIENT_SHARE`` of
  the run's events), as a probability density in bins of 1/5 decade, and the Clauset–Shalizi–Newman
  power-law fit through the chain model's public ``bifurcation.models.chain.clauset.clauset_fit``
  (``FIT``; its table: x_min, α, b, KS distance, bootstrap p, likelihood-ratio verdict). Sizes are
  potencies; a seismic moment is M0 = μP (rigidity μ), so b_M = 1.5 b_P with b_P = α − 1 (clauset.py).
  A run is not fitted when its kept sizes are fewer than ``MIN_FIT`` or span less than ``MIN_DECADES``
  (a chain of characteristic system-spanning events has no tail to fit); the table says which;
* **space–time**: each event's hypocentre (0-based block, as the catalog stores it) against its start
  time, marker area ∝ n_blocks, colour log10 P, the transient's end dashed;
* **stress balance**: ``balance_max`` of every run with events against its events done, with the flag
  ``BALANCE_FLAG`` (a 1e-6 relative error in k shows as > 1e-8 on every event: tests/test_rs_chain.py).

Everything is computed from the store: the same store gives the same tables and PNG bytes on one
machine (tests/test_rs_chain_report.py). What depends on the CPU is the catalog itself (docs/rs-chain.md).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

__all__ = ["BALANCE_FLAG", "FIT", "MAX_DRAWN", "MAX_RUNS", "MIN_DECADES", "MIN_FIT", "TRANSIENT_SHARE", "SizeFit",
           "blocks", "describe_label", "size_fit"]

#: Rows of the runs table (the first runs in store order; the rest are counted).
MAX_RUNS = 40
#: Runs drawn and fitted (evenly spread over the runs with events).
MAX_DRAWN = 6
#: Share of each run's first events dropped before the size statistics (the growth out of the random start).
TRANSIENT_SHARE = 0.1
#: Fewest kept positive sizes, and least span max/min in decades, for a power-law fit.
MIN_FIT = 50
MIN_DECADES = 1.0
#: ``clauset_fit``'s settings: 100 bootstrap samples (p to about ±0.05), 200 moving-block resamples for
#: α's error, x_min searched over 10 data values per decade (bounded cost on 10^5-event catalogs), seed 1.
FIT = {"bootstrap": 100, "block_bootstrap": 200, "seed": 1, "resolution": 10}
#: A run whose largest stress-balance residual exceeds this is flagged.
BALANCE_FLAG = 1e-8


def describe_label(label: str):
    """The state law's equation and source (the model's ``describe_label`` hook)."""
    from types import SimpleNamespace

    from ..rate_state.laws import resolve_state_law

    law = resolve_state_law(label)
    return SimpleNamespace(equation=law.equation, source=law.source)


@dataclass(frozen=True)
class SizeFit:
    """The size statistics of one run: the sizes kept after the transient, the fit or why there is none."""

    dropped: int            #: first events left out (the transient)
    sizes: np.ndarray       #: potencies of the kept events (catalog order)
    fit: object = None      #: ``clauset.PowerLawFit`` or None
    reason: str = ""        #: why not fitted (empty when fitted)


def size_fit(potency) -> SizeFit:
    """Drop the transient of the catalog's ``potency`` (catalog order) and fit what is left (``FIT``)."""
    from ..chain.clauset import clauset_fit

    p = np.asarray(potency, dtype=float)
    dropped = int(math.floor(TRANSIENT_SHARE * p.size))
    kept = p[dropped:]
    positive = kept[kept > 0]
    if positive.size < MIN_FIT:
        return SizeFit(dropped, kept, None, f"{positive.size} events after the transient (< {MIN_FIT})")
    span = math.log10(positive.max() / positive.min())
    if span < MIN_DECADES:
        return SizeFit(dropped, kept, None, f"sizes span {span:.2g} decades (< {MIN_DECADES:g}): no tail to fit")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")     # powerlaw's optimisers warn on edge cases (clauset.py)
        with np.errstate(all="ignore"):
            return SizeFit(dropped, kept, clauset_fit(kept, **FIT))


def _fit_row(label: str, s: SizeFit) -> list:
    if s.fit is None:
        return [label, str(s.sizes.size), "-", "-", "-", "-", "-", "-", f"not fitted: {s.reason}"]
    f = s.fit
    verdict = f.verdict()
    if f.alpha >= 19.99:        # the top of clauset_fit's α range [1, 20]
        verdict = "α at the search bound 20: no power-law tail; " + verdict
    # CSN's p tests the sizes above x_min only: a tail shorter than MIN_DECADES (e.g. the largest 0.1 %,
    # all system-spanning) passes it without being a scale-free law, so no power-law reading is given
    tail_span = math.log10(float(np.max(s.sizes)) / f.xmin) if f.xmin > 0 else math.nan
    if not tail_span >= MIN_DECADES:
        verdict = (f"no power-law reading: the tail ({f.n_tail} of {s.sizes.size} sizes) spans {tail_span:.2g} "
                   f"decade (< {MIN_DECADES:g}); CSN's test: " + verdict)
    return [label, str(s.sizes.size), f"{f.n_tail}", f"{f.xmin:.4g}",
            f"{f.alpha:.3f} ± {f.alpha_error:.3f} (i.i.d. {f.alpha_err:.3f})",
            f"{f.b_potency:.3f}", f"{f.b_magnitude:.3f}", f"{f.ks:.4f}", verdict]


def blocks(ds, model, out=None, figures=None, stem: str = "") -> list:
    """Report blocks for an ``rs-chain`` store ``ds`` (the model's ``report`` hook); with ``out`` (a
    directory) also the size, space–time and stress-balance figures, their paths appended to ``figures``."""
    from ...report.document import Paragraph, Section, Table
    from ...report.study import note
    from ...store.catalog import open_catalog

    path = ds.attrs.get("store_path")
    dims = model.dims
    varying = [d for d in dims if ds.sizes[d] > 1]
    done = np.asarray(ds["done"].values)
    status = np.asarray(ds["status"].values)
    count = np.asarray(ds[model.catalog_count].values)
    balance = np.asarray(ds["balance_max"].values)
    names = {int(s): str(s) for s in model.statuses}
    catalog = open_catalog(path) if path is not None else None
    runs = [tuple(int(i) for i in index) for index in np.argwhere(done)]
    with_events = [r for r, index in enumerate(runs) if int(count[index]) > 0]
    drawn = ({with_events[int(i)] for i in np.linspace(0, len(with_events) - 1, min(MAX_DRAWN, len(with_events))).round()}
             if with_events and catalog is not None else set())
    rows, fits, panels = [], [], []
    for r, index in enumerate(runs):
        if r >= MAX_RUNS and r not in drawn:
            continue
        k = int(count[index])
        cells = [str(np.asarray(ds[d].values)[i]) for d, i in zip(dims, index) if d in varying]
        mean_p = big = spanning = "-"
        if catalog is not None and k:
            wanted = ["potency", "n_blocks", "t_start", "hypocentre"] if r in drawn else ["potency", "n_blocks"]
            cat = catalog.read(int(np.ravel_multi_index(index, done.shape)), k, wanted)
            n = int(ds["n"].values[index[dims.index("n")]])
            mean_p = f"{float(np.mean(cat['potency'])):.6g}"
            big = str(int(np.max(cat["n_blocks"])))
            spanning = f"{float(np.mean(cat['n_blocks'] == n)):.3f}"
            if r in drawn:
                label = ", ".join(f"{d} = {c}" for d, c in zip(varying, cells)) or "the run"
                note(f"{label + ': ' if varying else ''}fitting {k} event sizes (Clauset: {FIT['bootstrap']} bootstrap samples and "
                     f"{FIT['block_bootstrap']} block resamples; minutes for 10^5 events)")
                s = size_fit(cat["potency"])
                fits.append((label, s))
                t = np.asarray(cat["t_start"], dtype=float)
                panels.append((label, t, np.asarray(cat["hypocentre"]), np.asarray(cat["n_blocks"]),
                               np.asarray(cat["potency"], dtype=float), float(t[s.dropped]) if s.dropped else math.nan,
                               n))
        if r < MAX_RUNS:
            rows.append((*cells, names.get(int(status[index]), str(int(status[index]))), str(k), mean_p, big, spanning,
                         f"{float(balance[index]):.1e}"))
    text = (f"{len(runs)} of {done.size} runs done. An event is a connected run of time in which some block slips "
            "faster than v_th; per-event catalogs are read with `bifurcation query --store S --catalog` (one run). "
            "The stress balance compares the change of Σ(μ_j + z_j + ηV_j) over an event with k(N V_lp Δt − ΔP) "
            "from the separately integrated potency (docs/rs-chain.md)."
            + (f" The first {MAX_RUNS} runs are listed." if len(runs) > MAX_RUNS else ""))
    body: list = [Paragraph(text)]
    if rows:
        body.append(Table((*varying, "status", "events", "mean potency", "largest event (blocks)",
                           "system-spanning share", "stress balance (max)"), tuple(rows)))
    checked = [i for i in runs if int(count[i]) > 0 and math.isfinite(float(balance[i]))]
    if checked:
        worst = max(float(balance[i]) for i in checked)
        flagged = sum(float(balance[i]) > BALANCE_FLAG for i in checked)
        body.append(Paragraph(
            f"Stress balance: the largest residual over the events of the {len(checked)} runs with events is "
            f"{worst:.1e}; {flagged} run(s) exceed the flag {BALANCE_FLAG:.0e} (a 1e-6 relative error in k shows "
            "as more than 1e-8 on every event, tests/test_rs_chain.py)."
            + (" Flagged runs are not a verified integration: rerun them with a smaller [engine] tolerance or "
               "fewer events per run (the absolute-time limit of docs/rs-chain.md)." if flagged else "")))
    if fits:
        body.append(Paragraph(
            f"Event sizes of {len(fits)} run(s) (evenly spread over the {len(with_events)} runs with events): sizes "
            f"are potencies P (moment M0 = μP for rigidity μ), the first {TRANSIENT_SHARE:.0%} of each run's events "
            "dropped as the transient out of the random start. The fit is Clauset, Shalizi and Newman's (SIAM Rev. "
            "51, 661 (2009)) through `powerlaw`, by the chain model's `clauset.clauset_fit`: p(P) ∝ P^−α above x_min, "
            f"x_min searched over {FIT['resolution']} data values per decade; α's error from "
            f"{FIT['block_bootstrap']} moving-block resamples (the catalog's events are correlated; the i.i.d. "
            f"error (α − 1)/√n_tail beside it); b_P = α − 1 (N(≥ P) ∝ P^−b_P) and b_M = 1.5 b_P in moment "
            f"magnitude; p from {FIT['bootstrap']} parametric-bootstrap samples (the power law is ruled out when "
            f"the one-sided 95 % Clopper–Pearson bound on p is ≤ 0.1, plausible when p > 0.1, undecided otherwise), "
            f"no power-law reading when the tail above x_min spans less than {MIN_DECADES:g} decade, the verdict with the likelihood ratios against the exponential, lognormal and truncated power "
            f"law (seed {FIT['seed']}). A run is fitted only with ≥ {MIN_FIT} sizes spanning ≥ {MIN_DECADES:g} decade. "
            "The KS distance is `powerlaw`'s D, whose empirical CDF is (i − 1)/n at the i-th smallest size, one side "
            "of each step (powerlaw-devs/powerlaw issue #111): the supremum over both sides can be up to 1/n_tail "
            "larger; the bootstrap p compares like with like."))
        body.append(Table(("run", "events kept", "n_tail", "x_min", "α ± error", "b_P", "b_M", "KS distance (powerlaw's D)",
                           "verdict"), tuple(_fit_row(label, s) for label, s in fits)))
    if out is not None and fits:
        note(f"drawing the size, space-time and stress-balance figures of {len(fits)} run(s)")
        body += _figures(out, figures, stem, fits, panels, runs, count, balance, varying, dims, ds)
    if out is not None:
        body.append(Paragraph(
            "Reproducibility: from one store this section's numbers and figures are the same bytes on one machine "
            "(the fits' random draws are seeded; tests/test_rs_chain_report.py). The catalog itself may depend on the "
            "CPU that computed it: heyoka compiles for the machine's vector width, and a chaotic chain's later events "
            "part ways for any two codes (docs/rs-chain.md); not compared across CPUs here. From the same store on "
            "another CPU, α is `powerlaw`'s closed-form estimate 1 + n_tail/Σ ln(P/x_min) (CSN Eq. 3.1), a sum "
            "of logarithms whose last bits follow numpy's SIMD width: far below the digits printed, unless a KS "
            "tie moves x_min (not checked). The PNG bytes depend also on matplotlib's and FreeType's versions."))
    return [Section("Rate-and-state chain runs and their catalogs", tuple(body), level=3)]


def _figures(out, figures, stem, fits, panels, runs, count, balance, varying, dims, ds) -> list:
    from pathlib import Path

    from ...report import figures as F
    from ...report.document import Figure
    from . import _report_figures as R

    out = Path(out)
    made = []

    def save(fig, name, caption):
        F.save(fig, out / name)
        if figures is not None:
            figures.append(out / name)
        made.append(Figure(name, caption))

    prefix = f"{stem}_" if stem else ""
    save(R.figure_sizes([(label, s.sizes, s.fit) for label, s in fits]), f"{prefix}rs_chain_sizes.png",
         f"Potency density of the events after the transient, {len(fits)} run(s), in bins of "
         f"1/{R.BINS_PER_DECADE} decade (points), and each fitted power law above its x_min (line; none where the "
         "table says not fitted).")
    save(R.figure_space_time(panels), f"{prefix}rs_chain_space_time.png",
         "Each event's hypocentre (0-based block) against its start time, marker area ∝ blocks slipped, colour "
         "log10 potency; left of the dashed line the transient left out of the size statistics.")
    checked = [i for i in runs if int(count[i]) > 0 and math.isfinite(float(balance[i]))]
    labels = [", ".join(f"{d} = {np.asarray(ds[d].values)[j]}" for d, j in zip(dims, i) if d in varying) for i in checked]
    save(R.figure_balance(labels, [int(count[i]) for i in checked], [float(balance[i]) for i in checked],
                          BALANCE_FLAG), f"{prefix}rs_chain_balance.png",
         f"Largest stress-balance residual over each run's events (balance_max; {len(checked)} runs), against its "
         f"events; dashed the flag {BALANCE_FLAG:.0e}.")
    return made
