"""Outcome of a slip cycle: result fields and status codes.

A grid never throws per point: each point carries a status. The codes are stable (they are stored).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..models.single_block import FIELD_ATTRS, FIELDS
from ..outcome import DEFAULT_MAX_STEPS, DEFAULT_T_MAX, Status

__all__ = ["DEFAULT_MAX_STEPS", "DEFAULT_T_MAX", "FIELDS", "FIELD_ATTRS", "SlipResult", "Status", "records",
           "status_names"]

class _Fields:
    """Key access, status names, records, xarray/pandas views and short reprs for the result dataclasses
    (which define ``keys``, ``_AXES``, the input fields that label the points, and ``_ATTRS``, the long
    names and units of their fields beyond ``FIELD_ATTRS``)."""

    _AXES: tuple = ()
    _ATTRS: dict = {}

    def __getitem__(self, key: str):
        return getattr(self, key)

    @property
    def shape(self) -> tuple:
        return np.shape(self.status)

    def to_xarray(self):
        """The points as an ``xarray.Dataset`` with one dimension ``point`` (flattened C order).

        The inputs (``_AXES``) are coordinates; ``status`` keeps its int8 codes with CF
        ``flag_values``/``flag_meanings``; every field has ``long_name`` and ``units``.
        """
        import xarray as xr

        attrs_of = {**FIELD_ATTRS, **self._ATTRS, **_AXIS_ATTRS}
        flat = {k: np.asarray(self[k]).ravel() for k in self.keys()}
        n = flat["status"].size

        def var(k):
            long_name, units = attrs_of[k]
            attrs = {"long_name": long_name, "units": units}
            if k == "status":
                attrs.update(flag_values=np.array([int(s) for s in Status], dtype=np.int8),
                             flag_meanings=" ".join(str(s) for s in Status))
            return ("point", flat[k], attrs)

        coords = {k: var(k) for k in self._AXES}
        data = {k: var(k) for k in self.keys() if k not in self._AXES}
        messages = [self.messages.get(i, "") for i in range(n)]
        if any(messages):
            data["message"] = ("point", np.array(messages, dtype=object), {"long_name": "why the status"})
        return xr.Dataset(data, coords=coords, attrs={"law": self.law, "precision": self.precision})

    def to_dataframe(self):
        """The points as a ``pandas.DataFrame``, one row per point, statuses as names."""
        import pandas as pd

        frame = pd.DataFrame({k: np.asarray(self[k]).ravel() for k in self.keys()})
        frame["status"] = status_names(frame["status"].to_numpy())
        frame.insert(0, "law", self.law)
        return frame

    def _status_counts(self) -> dict:
        names, counts = np.unique(status_names(np.asarray(self.status).ravel()), return_counts=True)
        return {str(k): int(v) for k, v in zip(names, counts)}

    def __repr__(self) -> str:
        return (f"{type(self).__name__}(law={self.law!r}, precision={self.precision!r}, "
                f"shape={self.shape}, statuses={self._status_counts()})")

    def _repr_html_(self) -> str:  # notebooks: a title line and the first rows as a table
        from html import escape

        frame = self.to_dataframe()
        more = f"<p>… {len(frame) - 20} more rows</p>" if len(frame) > 20 else ""
        return (f"<p><b>{escape(type(self).__name__)}</b> law <code>{escape(self.law)}</code>, "
                f"{escape(self.precision)} precision, {len(frame)} points, "
                f"{escape(str(self._status_counts()))}</p>" + frame.head(20).to_html(index=False) + more)

    def status_names(self) -> np.ndarray:
        """Status codes as strings ("stick-slip", ...), same shape."""
        return status_names(self.status)

    def to_records(self) -> list[dict]:
        """One dict per point (flattened C order), statuses as strings, NaN as None."""
        return records(self)


#: Long names and units of the inputs that label the points of a result.
_AXIS_ATTRS = {
    "nu": ("pulling speed ν (in V0)", "1"),
    "nu_f": ("friction velocity ν_f (in V0)", "1"),
}


@dataclass(frozen=True, repr=False)
class SlipResult(_Fields):
    """Arrays of one broadcast shape: the float ``FIELDS``, ``steps`` (int64) and ``status`` (int8 codes).

    Fields are reachable as attributes or keys (``r.delta``, ``r["delta"]``). ``messages`` maps a
    flat index to a message for points whose status is not stick-slip or creep.
    """

    nu: np.ndarray
    nu_f: np.ndarray
    delta: np.ndarray
    period: np.ndarray
    creep_time: np.ndarray
    slip_duration: np.ndarray
    stop_time: np.ndarray
    max_velocity: np.ndarray
    steps: np.ndarray
    status: np.ndarray
    messages: dict
    law: str
    precision: str

    _AXES = ("nu", "nu_f")

    def keys(self):
        return ("nu", "nu_f", *FIELDS, "steps", "status")


def status_names(codes) -> np.ndarray:
    """Status codes as strings ("stick-slip", ...), same shape (object array)."""
    names = np.full(max(Status) + 1, "", dtype=object)   # codes may have gaps (a retired code stays unused)
    for s in Status:
        names[int(s)] = str(s)
    return np.asarray(names[np.asarray(codes)], dtype=object)


def records(result) -> list[dict]:
    """Flatten a result (anything with ``keys()``, ``law``, ``messages``) to one dict per point."""
    flat = {k: np.asarray(result[k]).ravel() for k in result.keys()}
    out = []
    for i in range(next(iter(flat.values())).size):
        rec = {"law": result.law}
        for k, v in flat.items():
            if k == "status":
                rec[k] = str(Status(int(v[i])))
            elif k == "steps":
                rec[k] = int(v[i])
            else:
                x = float(v[i])
                rec[k] = x if np.isfinite(x) else None
        if i in result.messages:
            rec["message"] = result.messages[i]
        out.append(rec)
    return out
