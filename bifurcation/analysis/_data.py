"""Getting one-dimensional series out of stores (xarray Datasets).

A store (issue 3, ``bifurcation.open_store``) is an xarray Dataset with dimensions (law, nu_f, nu),
coordinates ``law`` (str), ``nu_f``, ``nu`` and the engine's fields as data variables, plus ``status``
(``bifurcation.Status`` codes) and ``done``. The analysis only ever needs a series along ν at fixed
(law, ν_f), or along ν_f at fixed (law, ν); these helpers find it, whichever of several stores holds it.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..engine import Status
from ..errors import InputError
from ..store.labels import RTOL, match_label, match_value

__all__ = ["FALLBACK_GRID", "Series", "coordinate_values", "cycles_along_nu", "fallback_grid", "find_stores",
           "load_stores", "match_nu_f", "series_along_nu", "series_along_nu_f", "slip_dataset"]

#: Relative tolerance for matching a requested ν_f or ν to a coordinate label (the one rule of
#: ``bifurcation.store.labels``): labels written as decimal text may differ in the last bit.
_LABEL_RTOL = RTOL
_GOOD = (int(Status.STICK_SLIP), int(Status.CREEP))

#: What ``fallback_grid`` computes (the critical-point workflow's ν and ν_f), for provenance lines.
FALLBACK_GRID = "Δ, T along ν = 1e-3 … 1e-15 (4/decade) at ν_f = 0.2, 0.3, 0.4, 0.5, both laws"


@dataclass(frozen=True)
class Series:
    """Points of one law along one axis, sorted by the axis, only finished good points.

    ``x`` is ν (``series_along_nu``) or ν_f (``series_along_nu_f``); ``fields`` maps a field name to
    its values; ``status`` the status codes.
    """

    law: str
    x: np.ndarray
    status: np.ndarray
    fields: dict = field(default_factory=dict)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.fields[name]

    def __len__(self) -> int:
        return int(self.x.size)


def _is_dataset(obj) -> bool:
    return hasattr(obj, "data_vars") and hasattr(obj, "coords")


def _sources(source) -> list:
    if source is None:
        return []
    if _is_dataset(source):
        return [source]
    if isinstance(source, Sequence) and not isinstance(source, (str, bytes)):
        out = []
        for s in source:
            out.extend(_sources(s))
        return out
    raise InputError("store", source, "is not a Dataset or a list of them",
                     "pass bifurcation.open_store(path), or analysis.slip_dataset(...) for points computed "
                     "in process")


def _laws_of(ds) -> list[str]:
    return [str(v) for v in np.atleast_1d(ds["law"].values)]


def _single_block(ds) -> bool:
    """The analysis reads (law, ν_f, ν) datasets of the single block (its theory: α, ω, the limit)."""
    from ..models import DEFAULT_MODEL
    from ..store.layout import store_model

    return store_model(ds.attrs) == DEFAULT_MODEL and set(ds["status"].dims) == {"law", "nu_f", "nu"}


def _law_index(ds, law: str) -> int | None:
    """Index of ``law`` among the dataset's laws, matched by identity (a formula by its expression)."""
    from ..models.single_block import law_identity

    try:
        return match_label("law", _laws_of(ds), law, law_identity).index
    except InputError:
        return None


def _dataset_series(ds, law: str, axis: str, fixed: float, fields, nearest: bool = False) -> Series | None:
    """The slice of ``ds`` along ``axis`` ("nu" or "nu_f") at the other coordinate = ``fixed`` (a label
    within ``RTOL``; the nearest label if ``nearest``)."""
    if not _single_block(ds):
        return None
    index = _law_index(ds, law)
    if index is None:
        return None
    other = "nu_f" if axis == "nu" else "nu"
    try:
        hit = match_value(other, ds[other].values, fixed, nearest=nearest, scale="log" if other == "nu" else "linear")
    except InputError:
        return None
    sub = ds.isel(law=index).isel({other: hit.index})
    x = np.asarray(sub[axis].values, dtype=float)
    status = np.asarray(sub["status"].values)
    good = np.isin(status, _GOOD) & np.asarray(sub["done"].values, dtype=bool)
    values = {f: np.asarray(sub[f].values, dtype=float) if f in sub else np.full(x.shape, np.nan)
              for f in fields}
    order = np.argsort(x)
    keep = good[order]
    return Series(str(sub["law"].values), x[order][keep], status[order][keep],
                  {k: v[order][keep] for k, v in values.items()})


def _series(source, law: str, axis: str, fixed: float, fields, *, what: str, nearest: bool = False) -> Series:
    stores = [ds for ds in _sources(source) if _single_block(ds)]
    holding = [ds for ds in stores if _law_index(ds, law) is not None]
    other = "nu_f" if axis == "nu" else "nu"
    if holding and not nearest:
        # the exact-label rule: a value that no store holds is refused, naming the nearest labels
        labels = np.unique(np.concatenate([np.asarray(ds[other].values, dtype=float) for ds in holding]))
        match_value(what, labels, fixed, scale="log" if other == "nu" else "linear")
    best = None
    for ds in holding:
        found = _dataset_series(ds, law, axis, fixed, fields, nearest=nearest)
        if found is not None and (best is None or len(found) > len(best)):
            best = found
    if best is None or len(best) == 0:
        hint = ""
        if stores:
            laws = sorted({l for ds in stores for l in _laws_of(ds)})
            hint = f" (stores hold laws {laws})"
        raise InputError(what, fixed, f"has no finished points for law {law!r}{hint}",
                         f"give a {what} value that the store holds, or run a workflow that covers it")
    return best


def coordinate_values(source, law: str, name: str) -> list[float]:
    """Sorted distinct values of coordinate ``name`` ("nu" or "nu_f") over the stores holding ``law``."""
    out: list[float] = []
    for ds in _sources(source):
        values = ds[name].values if _single_block(ds) and _law_index(ds, law) is not None else []
        for v in np.asarray(values, dtype=float):
            if not any(abs(v - u) <= _LABEL_RTOL * abs(v) for u in out):
                out.append(float(v))
    return sorted(out)


def series_along_nu(source, law: str, nu_f: float, fields=("delta", "period"), *, nearest: bool = False) -> Series:
    """Δ, T, … against ν at fixed (law, ν_f): the longest such series among the sources.

    ``nu_f`` must be a label of a store holding ``law`` (``bifurcation.store.labels``) unless ``nearest``.
    """
    return _series(source, law, "nu", _number("nu_f", nu_f), fields, what="nu_f", nearest=nearest)


def series_along_nu_f(source, law: str, nu: float, fields=("delta",), *, nearest: bool = False) -> Series:
    """Δ, … against ν_f at fixed (law, ν): the longest such series among the sources."""
    return _series(source, law, "nu_f", _number("nu", nu), fields, what="nu", nearest=nearest)


def match_nu_f(source, law: str, nu_f: float, *, nearest: bool = False):
    """The ν_f label (a ``bifurcation.store.labels.Match``) of the stores holding ``law`` that
    ``nu_f`` selects: equal within ``RTOL``, else refused naming the nearest labels, or with
    ``nearest`` the nearest one. Stores without ``law`` are ignored; no store with it is an error."""
    holding = [ds for ds in _sources(source) if _single_block(ds) and _law_index(ds, law) is not None]
    if not holding:
        from ..store.layout import store_model

        others = sorted({store_model(ds.attrs) for ds in _sources(source) if not _single_block(ds)})
        if others and not any(_single_block(ds) for ds in _sources(source)):
            raise InputError("store", f"model {', '.join(others)}",
                             "holds no Δ(ν) of the single block to extrapolate or fit (Δ, T and their ν → 0 "
                             "limit are the single-block model's outputs)",
                             "give a store of the single block (e.g. results/critical-point.zarr); for a chain "
                             "store use `bifurcation query --catalog` or `bifurcation report`")
        laws = sorted({l for ds in _sources(source) if _single_block(ds) for l in _laws_of(ds)})
        raise InputError("law", law, f"is in no store given (they hold {', '.join(laws) or 'no law'})",
                         "give a law the store holds (a formula matches by its expression)")
    labels = np.unique(np.concatenate([np.asarray(ds["nu_f"].values, dtype=float) for ds in holding]))
    return match_value("nu_f", labels, _number("nu_f", nu_f), nearest=nearest)


def _number(name: str, value) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        raise InputError(name, value, "is not a number", "give a number such as 0.4") from None


def cycles_along_nu(source, law: str, nu_f: float, *, nearest: bool = False):
    """ν, Δ, T and status along ν at (law, ν_f): finished good points with finite Δ and T.

    T falls back to Δ/ν (exact: the stuck phase reloads the spring by Δ) where a store lacks it.
    """
    s = series_along_nu(source, law, nu_f, fields=("delta", "period"), nearest=nearest)
    delta = s["delta"]
    period = np.where(np.isfinite(s["period"]), s["period"], delta / s.x)
    ok = np.isfinite(delta) & np.isfinite(period)
    return s.x[ok], delta[ok], period[ok], s.status[ok]


def find_stores(paths) -> list[Path]:
    """Store directories named by ``paths``: each a store, or a directory whose children are stores."""
    out = []
    for p in [Path(p) for p in ([paths] if isinstance(paths, (str, Path)) else paths)]:
        if not p.exists():
            raise InputError("store", str(p), "does not exist", "give the path of a store written by "
                             "`bifurcation submit`, or a directory that holds such stores")
        if _looks_like_store(p):
            out.append(p)
            continue
        children = sorted(c for c in p.iterdir() if c.is_dir() and _looks_like_store(c)) if p.is_dir() else []
        if not children:
            from ..store.zarr_store import _only_lock, only_lock_error

            if _only_lock(p):
                raise only_lock_error(p, "store")
            raise InputError("store", str(p), "is neither a Zarr store nor a directory of stores",
                             "give the path of a store written by `bifurcation submit`")
        out.extend(children)
    return out


def _looks_like_store(p: Path) -> bool:
    return p.is_dir() and any((p / n).exists() for n in ("zarr.json", ".zgroup", ".zmetadata"))


def load_stores(paths) -> list:
    """Every store named by ``paths`` (see ``find_stores``) as an xarray Dataset, read into memory.

    Loaded, not lazy: the analysis takes hundreds of slices, and decoding the Zarr chunks for each one
    cost half of the report's time; the paper's stores are a few MB.
    """
    from ..store import open_store

    out = []
    from ..store import check_store

    for p in find_stores(paths):
        check_store(p, argument="store")   # a Zarr array or another format: one line, not zarr's error
        from ..store.integrity import StoreDamagedError, missing_chunks

        missing = missing_chunks(p)   # read as fill values below, not as an error
        if missing:
            raise StoreDamagedError(p, missing[0])
        try:
            ds = open_store(p).load()
        except Exception:   # a chunk that does not decode: name it and the repair, as query and export do
            from ..store.integrity import StoreDamagedError, scan

            damage, _, _ = scan(p)
            if damage:
                raise StoreDamagedError(p, damage[0]) from None
            raise
        ds.attrs.setdefault("store_path", str(p))
        out.append(ds)
    return out


def slip_dataset(laws, nu_f, nu, *, precision: str = "double"):
    """Compute a small grid with ``bifurcation.slip`` in process, laid out like a store.

    Dimensions (law, nu_f, nu), the engine's fields, ``status`` and ``done`` — what the analysis reads.
    For tests and for claims that need a few points no store holds; grids go through ``submit``.
    """
    import xarray as xr

    from ..engine import FIELDS, slip

    laws = [laws] if isinstance(laws, str) else list(laws)
    nu_f = np.atleast_1d(np.asarray(nu_f, dtype=float))
    nu = np.atleast_1d(np.asarray(nu, dtype=float))
    data = {f: [] for f in (*FIELDS, "steps", "status")}
    for law in laws:
        # scalar (batch=1), as the store computes by default: the same bits as a stored study
        r = slip(law, nu=nu[None, :], nu_f=nu_f[:, None], precision=precision, batch=1)
        for f in data:
            data[f].append(np.asarray(r[f]))
    dims = ("law", "nu_f", "nu")
    variables = {f: (dims, np.stack(v)) for f, v in data.items()}
    variables["done"] = (dims, np.ones((len(laws), nu_f.size, nu.size), dtype=bool))
    return xr.Dataset(variables, coords={"law": np.array(laws, dtype=str), "nu_f": nu_f, "nu": nu},
                      attrs={"source": f"bifurcation.slip in process ({precision})"})


@functools.cache
def fallback_grid():
    """The series the report and the claims need along ν (``FALLBACK_GRID``), computed in process once.

    Used only when no store holds them; callers record that in their provenance. Do not modify the
    returned Dataset: it is shared.
    """
    return slip_dataset(["piecewise-linear", "carlson-langer"], [0.2, 0.3, 0.4, 0.5], np.logspace(-3, -15, 49))
