"""The lone-block nucleation of the compiled chain engine: one stored trajectory per run and end type.

A block that starts (σ = 1, V = 0) while both chain neighbours are stuck slips, until one of them or
a far block starts, along one trajectory that depends only on (law, ν, ν_f, ℓ, σ_f) and its end type:
in the engine's scaled variables (``_integrator``: U = U(t_s) + ν w, V = ν v, τ = t − t_s)

    ẇ = v,   v̇ = −k w + τ + g_σ(ν v/ν_f)/ν,   w(0) = v(0) = 0,

k = 2ℓ² + 1 (interior, ``selfc`` 0), ℓ² + 1 (free end, 1) or 1 (a lone block, N = 1: 2), and a stuck
neighbour's (σ − 1)/ν is d_n/ν + ℓ² w(τ) + τ, increasing in τ. So it is integrated once, by heyoka's
Taylor method (the exact engine's window integrator built at M = 1, a private copy: its law, switch
events and the fading laws' rungs, tolerance ε = 2.2e-16), and stored step by step as heyoka's Taylor polynomials
(order 20). The compiled engine (``_compiled.run_events``) then ends a lone event at the stored stop
with no integration, or hands the state at a neighbour's start (a monotone root on the polynomial) or
at a far block's start to DOP853.
"""

from __future__ import annotations

import threading
from collections import namedtuple

import numpy as np

__all__ = ["Lone", "lone_tables", "trajectory"]

#: stored trajectories, concatenated: steps [off[k], off[k + 1]) belong to selfc = k; per step its start
#: time t0 (t0[off[k + 1]] ... the next kind's; the end of the last step is ``sc[k, 0]``), Taylor
#: coefficients of w and v about t0, the law's piece, the largest v before the step, and the
#: step's maximum of v (offset from t0) and its value. sc[k] = (T, W_T, Vmax,
#: steps, valid): the stop time, w there, the largest v, heyoka's steps.
Lone = namedtuple("Lone", "off t0 t1 cw cv piece pre imt imv sc")

_MAX_STEPS = 100_000
#: this module's own M = 1 integrators (law, drop): not the exact engine's cached ones, whose state and
#: velocity-maximum recorder a chain run of that engine owns while it runs (threads of one process)
_PRIVATE: dict = {}
_LOCK = threading.Lock()


def _integrator(law, drop: bool):
    from ._integrator import _build

    key = (law.name, law.formula, drop)
    wi = _PRIVATE.get(key)
    if wi is None:
        wi = _PRIVATE[key] = _build(law, 1, "double", False, False, drop)
    return wi


def _poly(c, x):
    y = np.zeros_like(np.asarray(x, dtype=float)) + c[-1]
    for a in c[-2::-1]:
        y = y * x + a
    return y


def trajectory(law, nu: float, nu_f: float, ell: float, sigma: float, selfc: int) -> dict | None:
    """The lone block's trajectory from its start to its stop (None if heyoka did not reach a stop:
    the engine then integrates such events by DOP853)."""
    import heyoka as hy

    from ._lawtape import law_tape

    drop = sigma > 0.0
    wi = _integrator(law, drop)            # (under _LOCK: lone_tables)
    ta = wi.integrator
    l2 = ell * ell
    k = l2 * (2.0 - selfc) + 1.0
    kp = wi.n_pieces
    slots = wi.params      # the window's named parameter slots (_layout.WindowParams, M = 1)
    ta.pars[:] = slots.pack(nu=nu, nu_f=nu_f, l2=l2, p=[1.0], d=[0.0], q=[1.0], bond=[0.0], selfc=[float(selfc)],
                            pieces=[0], drop=(sigma, 1.0 - sigma) if drop else ())
    ta.state[:] = 0.0
    ta.time = 0.0
    ta.reset_cooldowns()
    g_break = law_tape(law).g_break
    pc = 0
    t0s, t1s, cws, cvs, pcs = [], [], [], [], []
    for _ in range(_MAX_STEPS):
        t0 = float(ta.time)
        oc, _h = ta.step()
        t1 = float(ta.time)
        if t1 > t0:
            t0s.append(t0), t1s.append(t1), pcs.append(pc)
            cws.append(ta.tc[0].copy()), cvs.append(ta.tc[1].copy())
        if oc == hy.taylor_outcome.success:
            continue
        index = -int(oc) - 1
        if not 0 <= index < len(wi.event_kind):
            return None                                  # non-finite
        kind = wi.event_kind[index]
        if kind == "rung":
            continue
        if kind == "block":                              # the stop
            break
        b = wi.event_break[index]                        # a switch: the side by the direction of x
        gb = float(g_break[b])
        if drop:
            gb = sigma + (1.0 - sigma) * gb
        rate = (-k * float(ta.state[0]) + t1) + gb / nu
        new = b + 1 if rate > 0 else b if rate < 0 else pc
        if new != pc:
            ta.pars[slots.selector(pc, 0)] = 0.0
            ta.pars[slots.selector(new, 0)] = 1.0
            pc = new
    else:
        return None
    w_end = float(ta.state[0])
    if not (np.isfinite(w_end) and w_end > 0.0) or -k * w_end + t1s[-1] >= 0.0:
        return None       # no stop, or σ ≥ 1 at the stop (it could not stick): left to DOP853
    t0 = np.array(t0s)
    t1 = np.array(t1s)
    cw, cv = np.array(cws), np.array(cvs)
    s = t0.size
    pre = np.zeros(s)
    imt = np.full(s, -1.0)
    imv = np.zeros(s)
    best = 0.0
    for i in range(s):
        pre[i] = best
        h = t1[i] - t0[i]
        x = np.linspace(0.0, h, 65)
        v = _poly(cv[i], x)
        j = int(np.argmax(v))
        # golden section around the largest sample, also at either end: a maximum within the last
        # 1/64 of the step samples largest at its end (σ = 0.01, ν = 0.01, free end: 5.3e-7 below it)
        a, b = x[max(j - 1, 0)], x[min(j + 1, 64)]
        g = 0.6180339887498949
        for _ in range(100):
            c, d = b - g * (b - a), a + g * (b - a)
            if _poly(cv[i], c) > _poly(cv[i], d):
                b = d
            else:
                a = c
        imt[i] = 0.5 * (a + b)
        imv[i] = float(_poly(cv[i], imt[i]))
        best = max(best, imv[i])
        best = max(best, float(v[0]), float(v[-1]))
    return {"t0": t0, "t1": t1, "cw": cw, "cv": cv, "piece": np.array(pcs, dtype=np.int64), "pre": pre,
            "imt": imt, "imv": imv, "T": float(t1[-1]), "W": w_end, "vmax": best, "steps": s}


def lone_tables(law, n: int, ends: str, nu: float, nu_f: float, ell: float, sigma: float) -> Lone:
    """The trajectories this chain can use (interior and free end, or N = 1), concatenated for numba."""
    if ends == "periodic":
        kinds = (0,) if n >= 3 else ()        # N ≤ 2 periodic: a neighbour is met twice (not a lone block)
    else:
        kinds = (2,) if n == 1 else (1,) if n == 2 else (0, 1)
    with _LOCK:
        parts = {k: trajectory(law, nu, nu_f, ell, sigma, k) for k in kinds}
    order = 21
    off = np.zeros(4, dtype=np.int64)
    sc = np.zeros((3, 5))
    rows = []
    for k in range(3):
        p = parts.get(k)
        off[k] = sum(r["steps"] for r in rows)
        if p is not None:
            order = p["cw"].shape[1]
            rows.append(p)
            sc[k] = (p["T"], p["W"], p["vmax"], p["steps"], 1.0)
    off[3] = sum(r["steps"] for r in rows)

    def cat(key, shape=(0,), dtype=float):
        return (np.ascontiguousarray(np.concatenate([r[key] for r in rows])) if rows
                else np.zeros(shape, dtype=dtype))

    return Lone(off, cat("t0"), cat("t1"), cat("cw", (0, order)), cat("cv", (0, order)),
                cat("piece", dtype=np.int64), cat("pre"), cat("imt"), cat("imv"), sc)
