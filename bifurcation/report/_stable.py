"""Report digits that hold on any x86-64 CPU.

heyoka compiles its Taylor integrator for the host CPU (vector width, fused multiply-add), so the
engine's results on two machines differ in the last bits: by at most the engine's own error, ≤ 1e-14
relative (docs/engine.md, "Precision"). The fits of the report amplify such differences, some a lot (the
coefficient K2 of a 14-term expansion, the largest residual of a fit): a committed report rewritten on
another CPU changed in its last digits. So each fitted number is printed only to the digits that a
data change of that size cannot move: the fits are repeated on copies of the data whose Δ and T are
multiplied by 1 + ``PERTURBATION``·u (u in [−1, 1], a hash of the point's labels and a seed: the same on
every machine, so the cut is too), and a number keeps only
the decimals above ``MARGIN`` times the largest change seen. A number that no digit of survives is
replaced by "(machine-dependent)".
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["MARGIN", "PERTURBATION", "SEEDS", "perturb", "spread", "stable"]

#: Relative size of the perturbation: the data error the fits assume (``analysis.period_fit``
#: ``DEFAULT_RELATIVE_ERROR``; the engine's median error against real128 is ~1e-16, docs/engine.md "Precision").
PERTURBATION = 2.2e-16
#: Seeds of the perturbed repetitions.
SEEDS = (11, 12, 13)
#: Kept decimals are at least this many times the largest change seen: a few repetitions sample the
#: change a different CPU makes, they do not bound it.
MARGIN = 2.0
MACHINE_DEPENDENT = "(machine-dependent)"


def _mix(x: np.ndarray) -> np.ndarray:
    """splitmix64's finaliser: well-spread uint64 from uint64."""
    x = (x ^ (x >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    x = (x ^ (x >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return x ^ (x >> np.uint64(31))


def _uniform(ds, name: str, seed: int) -> np.ndarray:
    """u in [−1, 1) per point of ``ds[name]``, a function of the point's labels and ``seed`` only.

    Not of the data: the same point gets the same u on every CPU and in every dataset that holds it
    (a store, or the same points computed in process), so the digit cut made from it is the same.
    """
    import zlib

    with np.errstate(over="ignore"):
        h = np.full(ds[name].shape, np.uint64(seed) * np.uint64(0x9E3779B97F4A7C15), dtype=np.uint64)
        for axis, dim in enumerate(ds[name].dims):
            values = ds[dim].values
            if values.dtype.kind in "OUST":
                keys = np.array([zlib.crc32(str(v).encode()) for v in values], dtype=np.uint64)
            else:
                keys = np.asarray(values, dtype=np.float64).view(np.uint64)
            shape = [1] * h.ndim
            shape[axis] = -1
            h = _mix(h ^ _mix(keys.reshape(shape) + np.uint64(axis + 1)))
    return (h >> np.uint64(11)).astype(np.float64) / 2.0**52 - 1.0


def perturb(ds, seed: int):
    """A copy of the dataset ``ds`` with ``delta`` and ``period`` perturbed relatively by ``PERTURBATION``."""
    out = ds.copy(deep=True)
    for name in ("delta", "period"):
        if name in out:
            values = np.asarray(out[name].values, dtype=float)
            out[name].values = values * (1 + PERTURBATION * _uniform(out, name, seed))
    return out


def spread(reference, reruns, name: str) -> float:
    """Largest |rerun.name − reference.name| (inf where a rerun differs in kind, e.g. NaN)."""
    base = float(getattr(reference, name))
    worst = 0.0
    for other in reruns:
        value = float(getattr(other, name))
        if math.isnan(base) and math.isnan(value):
            continue
        d = abs(value - base)
        worst = max(worst, d if math.isfinite(d) else math.inf)
    return worst


def stable(value, change: float, spec: str) -> str:
    """``value`` formatted with ``spec`` (``".8f"``, ``".4g"``, ``".1e"``, ``"+.1e"``), cut to the
    digits that a change of ``MARGIN``·``change`` cannot move.

    A number that no digit of survives is not printed: ``(machine-dependent)``. (A bound such as the
    power of ten above |value| + ``MARGIN``·change still moved across a decade between simulated
    machines.)"""
    if value is None or not math.isfinite(value):
        return "—"
    text = format(value, spec)
    if change <= 0 or value == 0:
        return text
    if not math.isfinite(change):
        return MACHINE_DEPENDENT

    def bound() -> str:
        return MACHINE_DEPENDENT

    step = 10.0 ** math.ceil(math.log10(MARGIN * change))   # the finest decimal kept
    lead = math.floor(math.log10(abs(value)))
    kind, digits = spec[-1], int(spec.rstrip("efg").split(".")[-1] or 6)
    sign = "+" if spec.startswith("+") else ""
    if kind == "f":
        keep = min(digits, max(0, -round(math.log10(step))))
        if abs(value) < step:
            return bound()
        return format(round(value, keep), f"{sign}.{keep}f")
    significant = lead - round(math.log10(step)) + 1
    have = digits if kind == "g" else digits + 1
    if significant < 1:
        return bound()
    n = min(have, significant)
    if kind == "g":
        if lead + 1 > n:   # more integer digits than are kept: round to tens, hundreds, ...
            return format(round(value, n - lead - 1), f"{sign}.0f")
        return format(value, f"{sign}.{n}g")
    return format(value, f"{sign}.{n - 1}e")
