"""The ν → 0 limit computed directly, not by extrapolation (docs/physics.md).

For ν_f ≤ 1/2 the limit cycle is the orbit of the ν = 0 flow Ü = −U + g(U̇/ν_f) that leaves the fixed
point along the fast eigen-direction; Δ0 is the displacement along it until U̇ returns to 0. It is
integrated with the law's compiled integrator (forcing off, ν = 1 so W = U) from a start on the
high-order manifold series (``manifold``), so neither the curvature of the manifold nor the rounding
of a tiny start offset limits the result. For ν_f > 1/2 the limit is creep: Δ0 = 0 and Δ/ν tends to
the linear-theory coefficient of Eqs. (9)–(10) (corrected, see ``bifurcation.theory``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mpmath
import numpy as np

from ..laws import FrictionLaw, resolve_law
from ._integrator import compiled
from ._validate import check_nu_f, check_precision
from .cycle import DEFAULT_MAX_STEPS, DEFAULT_T_MAX, run_cycle
from .manifold import _DPS as _MANIFOLD_DPS
from .manifold import fast_manifold_start
from .result import Status, _Fields

__all__ = ["LIMIT_FIELDS", "LimitResult", "limit"]

LIMIT_FIELDS = ("delta0", "max_velocity0", "slip_duration0", "tau1", "creep_coefficient", "stop_time0")

#: Long names and units of the limit fields (the xarray view of a ``LimitResult``).
LIMIT_FIELD_ATTRS = {
    "delta0": ("slip Δ0 per cycle as ν → 0, 0 in creep (in F0/k)", "1"),
    "max_velocity0": ("maximum block velocity on the limit orbit (in V0)", "1"),
    "slip_duration0": ("time from U̇ = ν_f to the stop, τ2 of Eq. 17 (in √(m/k))", "1"),
    "tau1": ("time between the crossings of U̇ = ν_f, Eq. 16 (in √(m/k))", "1"),
    "creep_coefficient": ("lim Δ/ν as ν → 0 for ν_f > 1/2 (in F0/k per V0)", "1"),
    "stop_time0": ("t0 of Eq. 9 for ν_f > 1/2 (in √(m/k))", "1"),
}


@dataclass(frozen=True, repr=False)
class LimitResult(_Fields):
    """ν → 0 limit per ν_f.

    ``delta0``: Δ0 (0 for ν_f > 1/2). ``max_velocity0``: max U̇ along the limit orbit.
    ``slip_duration0``: time from U̇ = ν_f to the stop (τ2 of Eq. 17 for Eq. 12; NaN where U̇ never
    reaches ν_f). ``tau1``: time from the first to the second crossing of U̇ = ν_f (Eq. 16; NaN if
    none). ``creep_coefficient``: lim Δ/ν for ν_f > 1/2 (Eq. 10 corrected), NaN otherwise.
    ``stop_time0``: t0 of Eq. (9) for ν_f > 1/2, NaN otherwise.
    """

    nu_f: np.ndarray
    delta0: np.ndarray
    max_velocity0: np.ndarray
    slip_duration0: np.ndarray
    tau1: np.ndarray
    creep_coefficient: np.ndarray
    stop_time0: np.ndarray
    steps: np.ndarray
    status: np.ndarray
    messages: dict
    law: str
    precision: str

    _AXES = ("nu_f",)
    _ATTRS = LIMIT_FIELD_ATTRS

    def keys(self):
        return ("nu_f", *LIMIT_FIELDS, "steps", "status")


def _to_fp(value, dtype):
    return dtype(mpmath.nstr(value, 45)) if dtype is not np.float64 else float(value)


def _stick_slip_limit(law: FrictionLaw, nu_f: float, precision: str, given=None):
    """``given``: ν_f as the user gave it; in quad its decimal text is read exactly (engine._exact), by the
    60-digit manifold start and by the real128 orbit alike, not through the nearest double."""
    from ._exact import at_precision, decimal_text

    c = compiled(law, precision)
    dtype = c.dtype
    text = decimal_text(given) if precision == "quad" and given is not None else None
    nu_f_fp = at_precision(given, dtype) if text is not None else dtype(nu_f)
    y_start = min(1e-3, 0.5 * law.breakpoints[0]) if law.breakpoints else 1e-3
    try:
        with mpmath.workdps(_MANIFOLD_DPS):   # the decimal read at the manifold's own precision
            U, Ud = fast_manifold_start(law, mpmath.mpf(text) if text is not None else nu_f, y_start=y_start)
    except ValueError as exc:
        return (math.nan,) * 4 + (0, Status.NONFINITE, str(exc))
    # The creep event marks U̇ = ν_f; run_cycle records it and every later crossing of breakpoint 1.
    raw = run_cycle(c, {"nu": dtype(1), "nu_f": nu_f_fp, "forcing": dtype(0)},
                    state0=(_to_fp(U, dtype), _to_fp(Ud, dtype)), t_max=DEFAULT_T_MAX, max_steps=DEFAULT_MAX_STEPS)
    if raw["status"] is not Status.STICK_SLIP:
        return (math.nan,) * 4 + (raw["steps"], raw["status"], raw["message"])
    x_max = float(raw["vmax"]) / nu_f
    x_checked = c.info.get("x_checked", math.inf)
    if x_max > x_checked:  # past the ladder's range (docs/engine.md, "Friction that fades")
        return (math.nan,) * 4 + (raw["steps"], Status.UNRESOLVED,
                                  f"U̇/ν_f reached {x_max:.3g}, beyond x = {x_checked:.3g} up to which the "
                                  "engine checked that no Taylor step can step over this law's friction")
    t_reach = raw["creep_time"]
    crossings = [t for t in raw["crossings"] if t > t_reach] if not math.isnan(t_reach) else []
    return (float(raw["W"]), float(raw["vmax"]),
            float(raw["time"] - t_reach) if not math.isnan(t_reach) else math.nan,
            float(crossings[0] - t_reach) if crossings else math.nan,
            raw["steps"], Status.STICK_SLIP, "")


def limit(law: str | FrictionLaw, *, nu_f, precision: str = "double") -> LimitResult:
    """Δ0(ν_f) = lim_{ν→0} Δ(ν, ν_f), computed directly on the ν = 0 flow.

    Parameters
    ----------
    law : str or FrictionLaw
        A law name or formula (see ``bifurcation.laws``).
    nu_f : array_like
        Friction velocities ν_f > 0.
    precision : {"double", "quad"}
        Integration precision of the orbit (the manifold start is computed at 60 digits either way).
    """
    from ..theory import linear

    law = resolve_law(law)
    check_precision(precision)
    nu_f_arr = check_nu_f(nu_f)
    shape = nu_f_arr.shape
    given = np.broadcast_to(np.asarray(nu_f, dtype=object), shape) if precision == "quad" else None
    out = {k: np.full(shape, np.nan) for k in LIMIT_FIELDS}
    steps = np.zeros(shape, dtype=np.int64)
    status = np.zeros(shape, dtype=np.int8)
    messages = {}
    for i, idx in enumerate(np.ndindex(shape)):
        nf = float(nu_f_arr[idx])
        if nf > 0.5:
            out["delta0"][idx] = 0.0
            out["creep_coefficient"][idx] = linear.creep_coefficient(nf)
            out["stop_time0"][idx] = linear.stop_time_creep(nf)
            status[idx] = int(Status.CREEP)
            continue
        d0, vmax, dur, tau1, n, st, msg = _stick_slip_limit(law, nf, precision,
                                                            given[idx] if given is not None else None)
        out["delta0"][idx], out["max_velocity0"][idx] = d0, vmax
        out["slip_duration0"][idx], out["tau1"][idx] = dur, tau1
        steps[idx], status[idx] = n, int(st)
        if msg:
            messages[i] = msg
    return LimitResult(nu_f=np.array(nu_f_arr, dtype=float), steps=steps, status=status,
                       messages=messages, law=law.name, precision=precision, **out)
