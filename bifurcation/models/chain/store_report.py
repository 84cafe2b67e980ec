"""A short section of ``bifurcation report --store`` for a chain store: its runs and their catalogs.

Per run (at most ``MAX_RUNS`` rows): the parameters that vary across the store, the status, the
events catalogued, and from the run's catalog the mean potency, the largest event (blocks) and the
share of system-spanning events (n_blocks = N). The full chain analysis (magnitude–frequency, b-value,
hysteresis) is ``bifurcation.models.chain.study``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["MAX_RUNS", "chain_store_blocks"]

#: Rows of the runs table (the first runs in store order; the rest are counted).
MAX_RUNS = 40


#: Runs drawn in the magnitude–frequency figure (evenly spread over the runs done).
MAX_DRAWN = 6


def chain_store_blocks(ds, model, out=None, figures=None, stem: str = "store") -> list:
    """Report blocks for the chain store ``ds`` (an ``open_store`` Dataset with ``store_path``); with
    ``out`` (a directory) also the magnitude–frequency figure of up to ``MAX_DRAWN`` runs, its path
    appended to ``figures``."""
    from ...store.catalog import open_catalog

    path = ds.attrs.get("store_path")
    dims = model.dims
    varying = [d for d in dims if ds.sizes[d] > 1]
    done = np.asarray(ds["done"].values)
    status = np.asarray(ds["status"].values)
    count = np.asarray(ds[model.catalog_count].values)
    names = {int(s): str(s) for s in model.statuses}
    catalog = open_catalog(path) if path is not None else None
    rows, runs = [], np.argwhere(done)
    drawn = {int(i) for i in np.linspace(0, len(runs) - 1, min(MAX_DRAWN, len(runs))).round()} if len(runs) else set()
    curves = []
    for r, index in enumerate(runs):
        if r >= MAX_RUNS and r not in drawn:
            continue
        index = tuple(int(i) for i in index)
        k = int(count[index])
        axes = {a.name: a for a in model.axes}   # a choice axis printed as its word (ends: free/periodic)
        cells = [str(axes[d].shown(ds[d].values[i].item()) if d in axes else ds[d].values[i].item())
                 for d, i in zip(dims, index) if d in varying]
        mean_p = big = spanning = "-"
        if catalog is not None and k:
            cat = catalog.read(int(np.ravel_multi_index(index, done.shape)), k, ["potency", "n_blocks"])
            n = int(ds["n"].values[index[dims.index("n")]])
            mean_p = f"{float(np.mean(cat['potency'])):.6g}"
            big = str(int(np.max(cat["n_blocks"])))
            spanning = f"{float(np.mean(cat['n_blocks'] == n)):.3f}"
            if r in drawn:
                label = ", ".join(f"{d} = {c}" for d, c in zip(varying, cells)) or "the run"
                curves.append((label, np.asarray(cat["potency"], dtype=float)))
        if r >= MAX_RUNS:
            continue
        rows.append([*cells, names.get(int(status[index]), str(int(status[index]))), str(k), mean_p, big, spanning])
    from ...report.document import Figure, Heading, Paragraph, Table

    blocks = [Heading("Chain runs and their catalogs", 3),
              Paragraph(f"{len(runs)} of {done.size} runs done; per-event catalogs are read with "
                    "`bifurcation query --store S --catalog` (one run) or `bifurcation.store.catalog.read_catalog`."
                    + (f" The first {MAX_RUNS} runs are listed." if len(runs) > MAX_RUNS else ""))]
    if rows:
        blocks.append(Table([*varying, "status", "events", "mean potency", "largest event (blocks)",
                             "system-spanning share"], rows))
    if out is not None and curves:
        from pathlib import Path

        from ...report import figures as F

        name = f"{stem}_magnitude_frequency.png"
        F.save(_figure_mfd(curves), Path(out) / name)
        if figures is not None:
            figures.append(Path(out) / name)
        blocks.append(Figure(name, f"Magnitude–frequency of {len(curves)} of the {len(runs)} runs: the number "
                                       "of catalogued events with potency ≥ P (every event of the catalog, "
                                       "the transient included)."))
    return blocks


def _figure_mfd(curves):
    """N(≥ P) against the potency P, one line per run (log–log)."""
    from ...report import figures as F

    fig, axes = F._figure(5.6, 4.0)
    ax = axes[0][0]
    for label, potency in curves:
        p = np.sort(potency[potency > 0])[::-1]
        if p.size:
            ax.step(p, np.arange(1, p.size + 1), where="post", lw=1.0, label=label)
    ax.set(xscale="log", yscale="log", xlabel="potency P = Σ slip of the event's blocks",
           ylabel="events with potency ≥ P", title="magnitude–frequency per run")
    ax.grid(alpha=0.25, lw=0.5, which="both")
    ax.legend(fontsize=7, frameon=False)
    return fig
