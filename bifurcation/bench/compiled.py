"""Compiled baselines of the single block: numbalsoda's DOP853 with numba right-hand sides.

numbalsoda (PyPI) wraps a Fortran DOP853 (its src/dop853_module.f90) behind ``solve_ivp``: a numba
``cfunc`` right-hand side and event function, called through C pointers with no Python in the loop,
and an event located by Brent's method on DOP853's 7th-order dense output. Every event is terminal.
The whole per-point loop is numba-compiled (``dop853_cycles``), so the cost measured is the
integrator's and the right-hand side's, as a user writing the fastest baseline would get.

Same scaled equations and events as the engine (``bifurcation.models.single_block``):
Ẅ = t − W + g(νẆ/ν_f)/ν from W = Ẇ = 0, stop at Ẇ = 0 (Δ = νW there), and for the
piecewise-linear law (Eq. 12) a switch of piece at νẆ/ν_f = 1, after which a new integration starts
from the located switch state. An event function is pinned away from zero at its segment's start
(numbalsoda tests every sign change, in either direction; the start sits on a zero).

Two settings of the baseline, measured and kept: ``t_eval = (t0, t_end)`` (numbalsoda otherwise
appends every step to a growing array: 2.5–3.5× slower here), and rtol = atol no tighter than 1e-14 (at
rtol = 3e-15 it silently lost a switch on the piecewise-linear law: Δ off by 2e-4 at ν = 1e-9, ν_f = 0.064).
Brent's tolerance in numbalsoda is 1e-8 in t (src/dop853_solve_ivp.f90, ``find_root``); Δ = νW at the
stop, where Ẇ = 0, so the stop's error enters Δ squared (≤ 1e-16), and the switches are kinks of the
right-hand side (its value is continuous), so theirs enters at second order too. What the baseline does
lose is switches: a velocity that crosses ν_f and back within one step shows no sign change (the bench
counts the points off by more than 1e-10 and checks the worst against the exact solution).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["LAW_IDS", "dop853_cycles"]

#: Laws the compiled baseline implements (a numba right-hand side per law, written out by hand).
LAW_IDS = {"carlson-langer": 0.0, "piecewise-linear": 1.0}
_T_END = 1e4
_kernels = None


def _build():
    """Compile the cfuncs and the per-point driver (numba is imported only for the bench)."""
    import numba as nb
    from numbalsoda import lsoda_sig, solve_ivp

    # data: [nu, nu_f, law id, piece, t0]
    @nb.cfunc(lsoda_sig)
    def rhs(t, u, du, p):
        d = nb.carray(p, (5,))
        nu, nu_f = d[0], d[1]
        if d[2] == 0.0:     # Carlson–Langer (Eq. 19): g(x) = x / (1 + x), g/ν = Ẇ/ν_f / (1 + x)
            g = u[1] / nu_f / (1.0 + nu * u[1] / nu_f)
        elif d[3] == 0.0:   # piecewise-linear (Eq. 12), x < 1: g/ν = Ẇ/ν_f
            g = u[1] / nu_f
        else:               # x > 1: g = 1
            g = 1.0 / nu
        du[0] = u[1]
        du[1] = t - u[0] + g

    @nb.cfunc(lsoda_sig)
    def events(t, u, g, p):
        d = nb.carray(p, (5,))
        if t > d[4]:
            g[0] = u[1]                           # stop: Ẇ = 0
            g[1] = d[0] * u[1] / d[1] - 1.0       # switch: x = 1
        else:                                     # the start: no event (see the module docstring)
            g[0] = 1.0
            g[1] = -1.0 if d[3] == 0.0 else 1.0

    rhs_ptr, events_ptr = rhs.address, events.address

    @nb.njit(cache=False)
    def cycle(nu, nu_f, law, rtol):
        p = np.array([nu, nu_f, law, 0.0, 0.0])
        y = np.zeros(2)
        t0 = 0.0
        n_events = 1 if law == 0.0 else 2
        for _ in range(16):
            p[4] = t0
            span = np.array([t0, _T_END])
            r = solve_ivp(rhs_ptr, span, y, span, "DOP853", n_events, events_ptr, p.ctypes.data,
                          0.0, 0.0, rtol, rtol)
            if not r.event_found:
                return math.nan
            if r.ind_event == 0:
                return nu * r.y_event[0]
            t0 = r.t_event
            y = r.y_event.copy()
            p[3] = 1.0 - p[3]
        return math.nan

    @nb.njit(cache=False)
    def cycles(nus, nu_fs, law, rtol):
        out = np.empty(nus.size)
        for i in range(nus.size):
            out[i] = cycle(nus[i], nu_fs[i], law, rtol)
        return out

    return cycles


def dop853_cycles(law: str, nu, nu_f, rtol: float = 1e-14) -> np.ndarray:
    """Δ at every point of the broadcast of ``nu`` and ``nu_f`` by numbalsoda's DOP853 (NaN: no stop).

    The first call compiles (a few seconds); time the later ones.
    """
    global _kernels
    if _kernels is None:
        _kernels = _build()
    nus, nu_fs = (np.ascontiguousarray(a, dtype=float).ravel() for a in np.broadcast_arrays(nu, nu_f))
    shape = np.broadcast_shapes(np.shape(nu), np.shape(nu_f))
    return _kernels(nus, nu_fs, LAW_IDS[law], float(rtol)).reshape(shape)
