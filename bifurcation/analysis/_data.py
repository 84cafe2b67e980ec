"""Getting one-dimensional series out of stores (xarray Datasets) or plain arrays.

A store (issue 3, ``bifurcation.open_store``) is an xarray Dataset with dimensions (law, nu_f, nu),
coordinates ``law`` (str), ``nu_f``, ``nu`` and the engine's fields as data variables, plus ``status``
(``bifurcation.Status`` codes) and ``done``. The analysis only ever needs a series along ν at fixed
(law, ν_f), or along ν_f at fixed (law, ν); these helpers find it, whichever of several stores holds it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..engine import Status
from ..errors import InputError

__all__ = ["Series", "coordinate_values", "find_stores", "load_stores", "series_along_nu", "series_along_nu_f",
           "slip_dataset"]

#: Relative tolerance for matching a requested ν_f or ν to a coordinate label: labels written as
#: decimal text in different workflows may differ in the last bits.
_LABEL_RTOL = 1e-9
_GOOD = (int(Status.STICK_SLIP), int(Status.CREEP))


@dataclass(frozen=True)
class Series:
    """Points of one law along one axis, sorted by the axis, only finished good points.

    ``x`` is ν (``series_along_nu``) or ν_f (``series_along_nu_f``); ``fixed`` the other coordinate;
    ``fields`` maps a field name to its values; ``status`` the status codes.
    """

    law: str
    axis: str
    x: np.ndarray
    fixed: float
    status: np.ndarray
    fields: dict = field(default_factory=dict)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.fields[name]

    def __len__(self) -> int:
        return int(self.x.size)

    def where(self, mask) -> "Series":
        mask = np.asarray(mask, dtype=bool)
        return Series(self.law, self.axis, self.x[mask], self.fixed, self.status[mask],
                      {k: v[mask] for k, v in self.fields.items()})


def _is_dataset(obj) -> bool:
    return hasattr(obj, "data_vars") and hasattr(obj, "coords")


def _sources(source) -> list:
    if source is None:
        return []
    if _is_dataset(source) or isinstance(source, Mapping) or hasattr(source, "keys"):
        return [source]
    if isinstance(source, Sequence) and not isinstance(source, (str, bytes)):
        out = []
        for s in source:
            out.extend(_sources(s))
        return out
    raise InputError("store", source, "is not a Dataset, a mapping of arrays or a list of them",
                     "pass bifurcation.open_store(path), or a dict with 'nu', 'nu_f' and field arrays")


def _match(labels: np.ndarray, value: float) -> np.ndarray:
    labels = np.asarray(labels, dtype=float)
    return np.abs(labels - value) <= _LABEL_RTOL * max(abs(value), 1e-300)


def _laws_of(ds) -> list[str]:
    return [str(v) for v in np.atleast_1d(ds["law"].values)]


def _dataset_series(ds, law: str, axis: str, fixed: float, fields) -> Series | None:
    """The slice of ``ds`` along ``axis`` ("nu" or "nu_f") at the other coordinate = ``fixed``."""
    if law not in _laws_of(ds):
        return None
    other = "nu_f" if axis == "nu" else "nu"
    hit = _match(ds[other].values, fixed)
    if not hit.any():
        return None
    sub = ds.sel(law=law).isel({other: int(np.flatnonzero(hit)[0])})
    x = np.asarray(sub[axis].values, dtype=float)
    status = np.asarray(sub["status"].values, dtype=float) if "status" in sub else np.full(x.shape, 1.0)
    status = np.where(np.isfinite(status), status, 0).astype(np.int64)
    good = np.isin(status, _GOOD)
    if "done" in sub:
        done = np.asarray(sub["done"].values)
        good &= np.where(np.isnan(done.astype(float)), False, done.astype(float) > 0)
    values = {}
    for f in fields:
        v = np.asarray(sub[f].values, dtype=float) if f in sub else np.full(x.shape, np.nan)
        values[f] = v
    order = np.argsort(x)
    keep = good[order]
    return Series(law, axis, x[order][keep], float(fixed), status[order][keep],
                  {k: v[order][keep] for k, v in values.items()})


def _mapping_series(m, law: str, axis: str, fixed: float, fields) -> Series | None:
    """The same from a mapping of equal-shape (or broadcastable) arrays, e.g. a ``SlipResult``."""
    m_law = getattr(m, "law", None) if not isinstance(m, Mapping) else m.get("law")
    if m_law is not None and str(m_law) != law:
        return None
    other = "nu_f" if axis == "nu" else "nu"
    arrays = {k: np.asarray(m[k]) for k in ("nu", "nu_f")}
    shape = np.broadcast_shapes(*(a.shape for a in arrays.values()),
                                *(np.asarray(m[f]).shape for f in fields if f in m.keys()))
    flat = {k: np.broadcast_to(a, shape).ravel().astype(float) for k, a in arrays.items()}
    sel = _match(flat[other], fixed)
    if not sel.any():
        return None
    keys = set(m.keys())
    status = (np.broadcast_to(np.asarray(m["status"]), shape).ravel().astype(np.int64)
              if "status" in keys else np.ones(flat["nu"].size, dtype=np.int64))
    good = sel & np.isin(status, _GOOD)
    x = flat[axis][good]
    order = np.argsort(x)
    values = {f: (np.broadcast_to(np.asarray(m[f], dtype=float), shape).ravel()[good][order]
                  if f in keys else np.full(x.size, np.nan)) for f in fields}
    return Series(law, axis, x[order], float(fixed), status[good][order], values)


def _series(source, law: str, axis: str, fixed: float, fields, *, what: str) -> Series:
    best = None
    seen = []
    for s in _sources(source):
        found = (_dataset_series if _is_dataset(s) else _mapping_series)(s, law, axis, fixed, fields)
        if _is_dataset(s):
            seen.append(s)
        if found is not None and (best is None or len(found) > len(best)):
            best = found
    if best is None or len(best) == 0:
        hint = ""
        if seen:
            other = "nu_f" if axis == "nu" else "nu"
            labels = sorted({float(v) for ds in seen if law in _laws_of(ds) for v in ds[other].values})
            laws = sorted({l for ds in seen for l in _laws_of(ds)})
            hint = f" (stores hold laws {laws}" + (f", {other} from {labels[0]:g} to {labels[-1]:g}, "
                                                  f"{len(labels)} values)" if labels else ")")
        raise InputError(what, fixed, f"has no finished points for law {law!r}{hint}",
                         f"give a {what} value that the store holds, or run a workflow that covers it")
    return best


def coordinate_values(source, law: str, name: str) -> list[float]:
    """Sorted distinct values of coordinate ``name`` ("nu" or "nu_f") over the stores holding ``law``."""
    out: list[float] = []
    for s in _sources(source):
        if _is_dataset(s):
            values = s[name].values if law in _laws_of(s) else []
        else:
            m_law = s.get("law") if isinstance(s, Mapping) else getattr(s, "law", None)
            values = np.asarray(s[name]).ravel() if m_law in (None, law) else []
        for v in np.asarray(values, dtype=float):
            if not any(abs(v - u) <= _LABEL_RTOL * abs(v) for u in out):
                out.append(float(v))
    return sorted(out)


def series_along_nu(source, law: str, nu_f: float, fields=("delta", "period")) -> Series:
    """Δ, T, … against ν at fixed (law, ν_f): the longest such series among the sources."""
    return _series(source, law, "nu", float(nu_f), fields, what="nu_f")


def series_along_nu_f(source, law: str, nu: float, fields=("delta",)) -> Series:
    """Δ, … against ν_f at fixed (law, ν): the longest such series among the sources."""
    return _series(source, law, "nu_f", float(nu), fields, what="nu")


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
            raise InputError("store", str(p), "is neither a Zarr store nor a directory of stores",
                             "give the path of a store written by `bifurcation submit`")
        out.extend(children)
    return out


def _looks_like_store(p: Path) -> bool:
    return p.is_dir() and any((p / n).exists() for n in ("zarr.json", ".zgroup", ".zmetadata"))


def load_stores(paths) -> list:
    """Open every store named by ``paths`` (see ``find_stores``) as an xarray Dataset."""
    try:
        from ..store import open_store
    except ImportError:  # the store package is not there: read the Zarr store with xarray directly
        import xarray as xr

        def open_store(path):
            return xr.open_zarr(path)
    out = []
    for p in find_stores(paths):
        ds = open_store(p)
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
        r = slip(law, nu=nu[None, :], nu_f=nu_f[:, None], precision=precision)
        for f in data:
            data[f].append(np.asarray(r[f]))
    dims = ("law", "nu_f", "nu")
    variables = {f: (dims, np.stack(v)) for f, v in data.items()}
    variables["done"] = (dims, np.ones((len(laws), nu_f.size, nu.size), dtype=bool))
    return xr.Dataset(variables, coords={"law": np.array(laws, dtype=str), "nu_f": nu_f, "nu": nu},
                      attrs={"source": f"bifurcation.slip in process ({precision})"})
