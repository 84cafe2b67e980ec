"""A short section of ``bifurcation report --store`` for a chain store: its runs and their catalogs.

Per run (at most ``MAX_RUNS`` rows): the parameters that vary across the store, the status, the
events catalogued, and from the run's catalog the mean potency, the largest event (blocks) and the
share of system-spanning events (n_blocks = N). The full chain analysis (magnitude–frequency, b-value,
hysteresis) is ``bifurcation.models.chain.report``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["MAX_RUNS", "chain_store_blocks"]

#: Rows of the runs table (the first runs in store order; the rest are counted).
MAX_RUNS = 40


def chain_store_blocks(ds, model, out=None, figures=None, stem: str = "") -> list:
    """Report blocks for the chain store ``ds`` (an ``open_store`` Dataset with ``store_path``); the
    model's ``report`` hook (it draws no figure: ``out``, ``figures`` and ``stem`` are unused)."""
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
    for index in runs[:MAX_RUNS]:
        index = tuple(int(i) for i in index)
        k = int(count[index])
        cells = [str(ds[d].values[i].item() if hasattr(ds[d].values[i], "item") else ds[d].values[i])
                 for d, i in zip(dims, index) if d in varying]
        mean_p = big = spanning = "-"
        if catalog is not None and k:
            cat = catalog.read(int(np.ravel_multi_index(index, done.shape)), k, ["potency", "n_blocks"])
            n = int(ds["n"].values[index[dims.index("n")]])
            mean_p = f"{float(np.mean(cat['potency'])):.6g}"
            big = str(int(np.max(cat["n_blocks"])))
            spanning = f"{float(np.mean(cat['n_blocks'] == n)):.3f}"
        rows.append([*cells, names.get(int(status[index]), str(int(status[index]))), str(k), mean_p, big, spanning])
    blocks = [("h3", "Chain runs and their catalogs"),
              ("p", f"{len(runs)} of {done.size} runs done; per-event catalogs are read with "
                    "`bifurcation query --store S --catalog` (one run) or `bifurcation.store.catalog.read_catalog`."
                    + (f" The first {MAX_RUNS} runs are listed." if len(runs) > MAX_RUNS else ""))]
    if rows:
        blocks.append(("table", [*varying, "status", "events", "mean potency", "largest event (blocks)",
                                 "system-spanning share"], rows))
    return blocks
