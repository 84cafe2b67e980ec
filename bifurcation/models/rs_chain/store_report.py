"""The rate-and-state chain's section of ``bifurcation report --store``: its runs and their catalogs.

Per run (at most ``MAX_RUNS`` rows): the parameters that vary across the store, the status, the
events catalogued, the mean potency, the largest event (blocks), the share of system-spanning events
(n_blocks = N) and the largest stress-balance residual of its events (``balance_max``). Catalogs are
read through the store's public reader ``bifurcation.store.catalog.open_catalog``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["MAX_RUNS", "blocks", "describe_label"]

#: Rows of the runs table (the first runs in store order; the rest are counted).
MAX_RUNS = 40


def describe_label(label: str):
    """The state law's equation and source (the model's ``describe_label`` hook)."""
    from types import SimpleNamespace

    from ..rate_state.laws import resolve_state_law

    law = resolve_state_law(label)
    return SimpleNamespace(equation=law.equation, source=law.source)


def blocks(ds, model, out=None, figures=None, stem: str = "") -> list:
    """Report blocks for an ``rs-chain`` store ``ds`` (the model's ``report`` hook; draws no figure)."""
    from ...report.document import Paragraph, Section, Table
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
    rows, runs = [], np.argwhere(done)
    for index in runs[:MAX_RUNS]:
        index = tuple(int(i) for i in index)
        k = int(count[index])
        cells = [str(np.asarray(ds[d].values)[i]) for d, i in zip(dims, index) if d in varying]
        mean_p = big = spanning = "-"
        if catalog is not None and k:
            cat = catalog.read(int(np.ravel_multi_index(index, done.shape)), k, ["potency", "n_blocks"])
            n = int(ds["n"].values[index[dims.index("n")]])
            mean_p = f"{float(np.mean(cat['potency'])):.6g}"
            big = str(int(np.max(cat["n_blocks"])))
            spanning = f"{float(np.mean(cat['n_blocks'] == n)):.3f}"
        rows.append((*cells, names.get(int(status[index]), str(int(status[index]))), str(k), mean_p, big, spanning,
                     f"{float(balance[index]):.1e}"))
    text = (f"{len(runs)} of {done.size} runs done. An event is a connected run of time in which some block slips "
            "faster than v_th; per-event catalogs are read with `bifurcation query --store S --catalog` (one run). "
            "The stress balance compares the change of Σ(μ_j + z_j + ηV_j) over an event with k(N V_lp Δt − ΔP) "
            "from the separately integrated potency (docs/rs-chain.md)."
            + (f" The first {MAX_RUNS} runs are listed." if len(runs) > MAX_RUNS else ""))
    body = [Paragraph(text)]
    if rows:
        body.append(Table((*varying, "status", "events", "mean potency", "largest event (blocks)",
                           "system-spanning share", "stress balance (max)"), tuple(rows)))
    return [Section("Rate-and-state chain runs and their catalogs", tuple(body), level=3)]
