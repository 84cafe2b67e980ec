"""Matching a requested value to the labels of a store axis: exact within a relative 1e-12, or an error.

Queries, ``extrapolate`` and ``fit-period`` all select points through here, so one rule holds
everywhere: a number matches a label when they agree to a relative ``RTOL`` (labels typed as decimal
text in two workflows may differ in the last bit; nothing else is the same point). Anything else is
an ``InputError`` that names the axis, the value and the nearest labels present, unless the caller
opts in to ``nearest``, and then the match says what was taken. Categorical labels (friction laws)
match by identity (``Labels.identity``: a formula by its parsed expression, not its text).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["Match", "RTOL", "match_label", "match_value", "nearest_labels"]

#: Relative agreement for a number to be a label: far above the rounding of a decimal (1.1e-16),
#: far below any grid spacing a study uses (the finest shipped one is 1e-3 relative).
RTOL = 1e-12


@dataclass(frozen=True)
class Match:
    """``index`` into the axis, the ``label`` found, the ``value`` asked for, ``exact`` or nearest."""

    axis: str
    value: object
    index: int
    label: object
    exact: bool

    def note(self) -> str:
        """One line for a nearest match (empty for an exact one)."""
        if self.exact:
            return ""
        return f"{self.axis}: no label {self.value!r}; took the nearest, {self.label!r}"


def _distance(labels: np.ndarray, value: float, scale: str) -> np.ndarray:
    if scale == "log" and value > 0 and np.all(labels > 0):
        return np.abs(np.log(labels) - math.log(value))
    return np.abs(labels - value)


def nearest_labels(labels, value: float, *, scale: str = "linear", count: int = 2) -> list[float]:
    """The ``count`` labels nearest to ``value`` (by ratio on a log axis), nearest first."""
    labels = np.asarray(labels, dtype=float)
    order = np.argsort(_distance(labels, value, scale), kind="stable")[:count]
    return [float(labels[i]) for i in order]


def match_value(axis: str, labels, value, *, nearest: bool = False, scale: str = "linear",
                argument: str | None = None, show=None) -> Match:
    """The label of ``labels`` equal to ``value`` within ``RTOL`` (relative), else the nearest one if
    ``nearest``, else ``InputError`` naming ``argument`` (default ``axis``) and the nearest labels.
    ``show``: how a label is printed (``Axis.shown``: ``16`` not ``16.0`` for a count, ``free`` for
    the chain's ends 0); the ``Match`` holds the printed forms."""
    argument = argument or axis
    shown = show or (lambda v: v)
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(argument, value, "is not a number", "give a number such as 0.4 or 1e-9") from None
    if not math.isfinite(x):
        raise InputError(argument, value, "is not finite", "give a finite number")
    labels = np.asarray(labels, dtype=float)
    if labels.size == 0:
        raise InputError(argument, value, "cannot match: the axis has no labels", "use another store")
    hit = np.flatnonzero(np.abs(labels - x) <= RTOL * max(abs(x), np.finfo(float).tiny))
    if hit.size:
        i = int(hit[np.argmin(np.abs(labels[hit] - x))])
        return Match(axis, shown(x), i, shown(float(labels[i])), True)
    near = nearest_labels(labels, x, scale=scale)
    if not nearest:
        listed = ", ".join(repr(shown(v)) for v in near)
        span = f"{shown(float(labels.min()))!r} … {shown(float(labels.max()))!r}, {labels.size} labels"
        raise InputError(argument, shown(x), f"is not a label of this store (nearest: {listed}; {span})",
                         "give one of its labels, or pass --nearest to take the nearest")
    i = int(np.flatnonzero(labels == near[0])[0])
    return Match(axis, shown(x), i, shown(near[0]), False)


def match_label(axis: str, labels, value, identity, *, argument: str | None = None) -> Match:
    """The categorical label of ``labels`` with the same ``identity`` as ``value`` (exact only)."""
    argument = argument or axis
    labels = [str(v) for v in labels]
    try:
        wanted = identity(str(value))
    except InputError:   # not a valid label at all: it can only be refused, naming the store's labels
        wanted = None
    for i, label in enumerate(labels):
        if wanted is None:
            break
        try:
            if identity(label) == wanted:
                return Match(axis, value, i, label, True)
        except InputError:   # a label this version cannot parse matches nothing
            continue
    # labels with commas ("prz, quasi-static": the rate-state branches) were unreadable joined by commas
    sep = "; " if any("," in label for label in labels) else ", "
    raise InputError(argument, value, f"is not a {axis} of this store", f"use one of {sep.join(labels)}")
