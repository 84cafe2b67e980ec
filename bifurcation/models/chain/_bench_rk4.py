"""Compiled (numba) fixed-step RK4 chains: the baselines of ``bifurcation bench --suite chain``.

The code a user who wants catalogs fast would write, with the semantics of the interpreted baseline
(``_bench.rk4_chain``): classical RK4 at a fixed step dt, a stuck block held by V̇ = max(σ − 1, 0),
negative velocities clipped to 0 after every step, an event over when no velocity is positive,
quiescent phases jumped exactly (t + (1 − max σ)/ν).

* ``rk4_plain``: the whole chain every step (O(N) per step).
* ``rk4_active``: only the *active set* (blocks that moved in the event and their neighbours) is
  stepped; the others are stuck and only their stress matters. O(N) per event (the stresses, the
  largest one outside the set), O(set) per step.

Laws: 0 Carlson–Langer 1/(1 + x), 1 piecewise-linear (Eq. 12), 2 exponential e^{−x}.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from ._numba_cache import CACHE

__all__ = ["LAW_CODES", "rk4_active", "rk4_plain"]

LAW_CODES = {"carlson-langer": 0, "piecewise-linear": 1, "exponential": 2}
_jit = nb.njit(cache=CACHE, nogil=True, error_model="numpy")   # (read-only cache: compile per process)


@_jit
def _phi(law, x):
    if law == 0:
        return 1.0 / (1.0 + x)
    if law == 1:
        return 1.0 - x if x < 1.0 else 0.0
    return math.exp(-x)


@_jit
def _lap(u, j, n, periodic):
    if periodic:
        return u[(j - 1) % n] - 2.0 * u[j] + u[(j + 1) % n]
    lf = u[j - 1] if j > 0 else u[j]
    rt = u[j + 1] if j < n - 1 else u[j]
    return lf - 2.0 * u[j] + rt


@_jit
def _acc_all(u, v, t, l2, nu, nu_f, law, periodic, out):
    n = u.size
    for j in range(n):
        s = l2 * _lap(u, j, n, periodic) - u[j] + nu * t
        out[j] = s - _phi(law, v[j] / nu_f) if v[j] > 0.0 else max(s - 1.0, 0.0)


@_jit
def rk4_plain(law, l2, nu, nu_f, periodic, u, events, dt, max_steps, out):
    """``events`` events from displacements u (changed in place), t = 0, all stuck.
    out[:, e] = potency, n_blocks, duration, max_velocity. Returns the steps taken."""
    n = u.size
    v = np.zeros(n)
    k1v, k2u, k2v, k3u, k3v, k4v = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
    tu, tv = np.zeros(n), np.zeros(n)
    moved = np.zeros(n, dtype=np.bool_)
    t = 0.0
    steps = 0
    for e in range(events):
        top = -np.inf
        for j in range(n):
            top = max(top, l2 * _lap(u, j, n, periodic) - u[j] + nu * t)
        t += (1.0 - top) / nu
        t0 = t
        p0 = 0.0
        for j in range(n):
            p0 += u[j]
            moved[j] = False
        vmax = 0.0
        while True:
            _acc_all(u, v, t, l2, nu, nu_f, law, periodic, k1v)
            for j in range(n):
                tu[j] = u[j] + 0.5 * dt * v[j]
                tv[j] = v[j] + 0.5 * dt * k1v[j]
            _acc_all(tu, tv, t + 0.5 * dt, l2, nu, nu_f, law, periodic, k2v)
            for j in range(n):
                k2u[j] = tv[j]
                tu[j] = u[j] + 0.5 * dt * k2u[j]
                tv[j] = v[j] + 0.5 * dt * k2v[j]
            _acc_all(tu, tv, t + 0.5 * dt, l2, nu, nu_f, law, periodic, k3v)
            for j in range(n):
                k3u[j] = tv[j]
                tu[j] = u[j] + dt * k3u[j]
                tv[j] = v[j] + dt * k3v[j]
            _acc_all(tu, tv, t + dt, l2, nu, nu_f, law, periodic, k4v)
            live = False
            for j in range(n):
                u[j] += dt / 6.0 * (v[j] + 2.0 * k2u[j] + 2.0 * k3u[j] + tv[j])
                v[j] = max(v[j] + dt / 6.0 * (k1v[j] + 2.0 * k2v[j] + 2.0 * k3v[j] + k4v[j]), 0.0)
                if v[j] > 0.0:
                    live = True
                    moved[j] = True
                    vmax = max(vmax, v[j])
            t += dt
            steps += 1
            if not live or steps > max_steps:
                break
        p1 = 0.0
        nb_ = 0
        for j in range(n):
            p1 += u[j]
            nb_ += moved[j]
        out[0, e] = p1 - p0
        out[1, e] = nb_
        out[2, e] = t - t0
        out[3, e] = vmax
    return steps


@_jit
def _acc_set(m, idx, loc, su, sv, u, t, l2, nu, nu_f, law, periodic, out):
    """Accelerations of the active set (positions 0..m−1 ↔ blocks idx) at stage values su, sv; a
    neighbour outside the set is stuck at u."""
    n = u.size
    for i in range(m):
        j = idx[i]
        if periodic:
            a, b = (j - 1) % n, (j + 1) % n
        else:
            a = j - 1 if j > 0 else j
            b = j + 1 if j < n - 1 else j
        ua = su[loc[a]] if loc[a] >= 0 else u[a]
        ub = su[loc[b]] if loc[b] >= 0 else u[b]
        s = l2 * (ua - 2.0 * su[i] + ub) - su[i] + nu * t
        out[i] = s - _phi(law, sv[i] / nu_f) if sv[i] > 0.0 else max(s - 1.0, 0.0)


@_jit
def _far(u, n, l2, nu, t, periodic, loc):
    """The largest stress outside the set at time t (−inf if none)."""
    top = -np.inf
    for j in range(n):
        if loc[j] < 0:
            top = max(top, l2 * _lap(u, j, n, periodic) - u[j] + nu * t)
    return top


@_jit
def _add(j, m, idx, loc, u, v, su0, n, periodic):
    for c in (j - 1, j, j + 1):
        if periodic:
            c = c % n
        elif c < 0 or c >= n:
            continue
        if loc[c] < 0:
            loc[c] = m
            idx[m] = c
            su0[m] = u[c]
            m += 1
    return m


@_jit
def rk4_active(law, l2, nu, nu_f, periodic, u, events, dt, max_steps, out):
    """As ``rk4_plain``, stepping only the active set."""
    n = u.size
    idx = np.zeros(n, dtype=np.int64)
    loc = np.full(n, -1, dtype=np.int64)
    v = np.zeros(n)
    su, sv, uu, vv = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
    k1, k2, k3, k4 = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
    k2u, k3u = np.zeros(n), np.zeros(n)
    moved = np.zeros(n, dtype=np.bool_)
    t = 0.0
    steps = 0
    for e in range(events):
        top = -np.inf
        h = 0
        for j in range(n):
            s = l2 * _lap(u, j, n, periodic) - u[j] + nu * t
            if s > top:
                top, h = s, j
        t += (1.0 - top) / nu
        t0 = t
        m = _add(h, 0, idx, loc, u, v, uu, n, periodic)
        far = _far(u, n, l2, nu, t, periodic, loc)
        t_far = t + (1.0 - far) / nu
        p0 = 0.0
        for i in range(m):
            vv[i] = 0.0
        vmax = 0.0
        while True:
            m0 = m
            _acc_set(m, idx, loc, uu, vv, u, t, l2, nu, nu_f, law, periodic, k1)
            for i in range(m):
                su[i] = uu[i] + 0.5 * dt * vv[i]
                sv[i] = vv[i] + 0.5 * dt * k1[i]
            _acc_set(m, idx, loc, su, sv, u, t + 0.5 * dt, l2, nu, nu_f, law, periodic, k2)
            for i in range(m):
                k2u[i] = sv[i]
                su[i] = uu[i] + 0.5 * dt * k2u[i]
                sv[i] = vv[i] + 0.5 * dt * k2[i]
            _acc_set(m, idx, loc, su, sv, u, t + 0.5 * dt, l2, nu, nu_f, law, periodic, k3)
            for i in range(m):
                k3u[i] = sv[i]
                su[i] = uu[i] + dt * k3u[i]
                sv[i] = vv[i] + dt * k3[i]
            _acc_set(m, idx, loc, su, sv, u, t + dt, l2, nu, nu_f, law, periodic, k4)
            live = False
            for i in range(m):
                du = dt / 6.0 * (vv[i] + 2.0 * k2u[i] + 2.0 * k3u[i] + sv[i])
                uu[i] += du
                p0 += du
                vv[i] = max(vv[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]), 0.0)
                if vv[i] > 0.0:
                    live = True
                    moved[idx[i]] = True
                    vmax = max(vmax, vv[i])
            t += dt
            steps += 1
            # the set grows around every moving block; a block outside it fails at t_far
            for i in range(m0):
                if vv[i] > 0.0:
                    m = _add(idx[i], m, idx, loc, u, v, uu, n, periodic)
            if t >= t_far:
                for j in range(n):
                    if loc[j] < 0 and l2 * _lap(u, j, n, periodic) - u[j] + nu * t >= 1.0:
                        m = _add(j, m, idx, loc, u, v, uu, n, periodic)
                live = True
            if m != m0:
                for i in range(m0, m):
                    vv[i] = 0.0
                far = _far(u, n, l2, nu, t, periodic, loc)
                t_far = t + (1.0 - far) / nu
            if not live or steps > max_steps:
                break
        nb_ = 0
        for i in range(m):
            j = idx[i]
            u[j] = uu[i]
            nb_ += moved[j]
            moved[j] = False
            loc[j] = -1
        out[0, e] = p0
        out[1, e] = nb_
        out[2, e] = t - t0
        out[3, e] = vmax
    return steps


def run_rk4(kind: str, law: str, *, n: int, ell: float, nu: float, nu_f: float, u0, events: int, dt: float,
            ends: str = "free", max_steps: int = 100_000_000) -> dict:
    """Catalog (potency, n_blocks, duration, max_velocity, steps) of ``rk4_plain``/``rk4_active``."""
    fn = {"plain": rk4_plain, "active": rk4_active}[kind]
    out = np.zeros((4, events))
    u = np.array(u0, dtype=np.float64)
    steps = fn(LAW_CODES[law], ell * ell, nu, nu_f, ends == "periodic", u, events, dt, max_steps, out)
    return {"potency": out[0], "n_blocks": out[1].astype(np.int64), "duration": out[2], "max_velocity": out[3],
            "steps": int(steps)}


# -- the presets at their own loading rate (ν = 0.01, σ > 0): events split in time by V_th ---------------
@_jit
def _acc_drop(j, su, sv, t, l2, nu, nu_f, sigma, law, n, periodic):
    """V̇_j with the friction drop: Φ_σ(x) = (1 − σ) Φ(x/(1 − σ)) while slipping; a stuck block holds
    any stress below 1 and starts at 1 with acceleration σ_j − (1 − σ) (one-way friction)."""
    s = l2 * _lap(su, j, n, periodic) - su[j] + nu * t
    if sv[j] > 0.0:
        return s - (1.0 - sigma) * _phi(law, sv[j] / (nu_f * (1.0 - sigma)))
    return s - (1.0 - sigma) if s >= 1.0 else 0.0


@_jit
def _join(j, m, idx, inset):
    if not inset[j]:
        inset[j] = True
        idx[m] = j
        return m + 1
    return m


@_jit
def _far_time(u, n, l2, nu, t, periodic, inset):
    """The earliest time a block outside the set reaches stress 1 (its neighbours are stuck)."""
    best = np.inf
    for j in range(n):
        if not inset[j]:
            s = l2 * _lap(u, j, n, periodic) - u[j] + nu * t
            best = min(best, t + (1.0 - s) / nu)
    return best


@_jit
def rk4_vth(law, l2, nu, nu_f, sigma, periodic, u, v, t, t_end, vth, dt, prune, out, tot):
    """Fixed-step RK4 of the chain with the friction drop σ from (u, v, t) (changed in place) to t_end,
    stepping only the active set (slipping blocks and their neighbours, stuck pairs pruned every ``prune``
    steps), V clipped at 0 after each step (no back-slip). Events split in time as ``_subevents``, read at
    step ends: open when some V_j > vth, closed when none; out[:, e] = t_start, potency, duration,
    hypocentre, n_blocks. tot += [steps, slip outside events, largest set]. Returns (events, t)."""
    n = u.size
    idx = np.zeros(n, dtype=np.int64)
    inset = np.zeros(n, dtype=np.bool_)
    stamp = np.zeros(n, dtype=np.int64)
    su, sv = u.copy(), v.copy()
    k1, k2, k3, k4 = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
    k2u, k3u = np.zeros(n), np.zeros(n)
    m = 0
    for j in range(n):
        if v[j] > 0.0:
            m = _join(j, m, idx, inset)
            m = _join((j - 1) % n if periodic else max(j - 1, 0), m, idx, inset)
            m = _join((j + 1) % n if periodic else min(j + 1, n - 1), m, idx, inset)
    t_far = _far_time(u, n, l2, nu, t, periodic, inset)
    ne = 0
    opened, t0, pot, hyp, nbl, eid = False, 0.0, 0.0, -1, 0, 0
    steps = 0
    while t < t_end and ne < out.shape[1]:
        if m == 0:                                  # all stuck: jump to the next failure exactly
            t = max(t, t_far)
            if t >= t_end:
                break
        if t >= t_far:                              # blocks outside the set at stress 1 join it
            for j in range(n):
                if not inset[j] and l2 * _lap(u, j, n, periodic) - u[j] + nu * t >= 1.0:
                    m = _join(j, m, idx, inset)
            t_far = _far_time(u, n, l2, nu, t, periodic, inset)
        for q in range(m):
            j = idx[q]
            k1[j] = _acc_drop(j, u, v, t, l2, nu, nu_f, sigma, law, n, periodic)
        for q in range(m):
            j = idx[q]
            su[j] = u[j] + 0.5 * dt * v[j]
            sv[j] = v[j] + 0.5 * dt * k1[j]
        for q in range(m):
            j = idx[q]
            k2[j] = _acc_drop(j, su, sv, t + 0.5 * dt, l2, nu, nu_f, sigma, law, n, periodic)
        for q in range(m):
            j = idx[q]
            k2u[j] = sv[j]
            su[j] = u[j] + 0.5 * dt * k2u[j]
            sv[j] = v[j] + 0.5 * dt * k2[j]
        for q in range(m):
            j = idx[q]
            k3[j] = _acc_drop(j, su, sv, t + 0.5 * dt, l2, nu, nu_f, sigma, law, n, periodic)
        for q in range(m):
            j = idx[q]
            k3u[j] = sv[j]
            su[j] = u[j] + dt * k3u[j]
            sv[j] = v[j] + dt * k3[j]
        for q in range(m):
            j = idx[q]
            k4[j] = _acc_drop(j, su, sv, t + dt, l2, nu, nu_f, sigma, law, n, periodic)
        slip = 0.0
        above = 0
        top, vtop = -1, 0.0
        for q in range(m):
            j = idx[q]
            du = dt / 6.0 * (v[j] + 2.0 * k2u[j] + 2.0 * k3u[j] + sv[j])
            u[j] += du
            su[j] = u[j]
            slip += du
            v[j] = max(v[j] + dt / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]), 0.0)
            sv[j] = v[j]
            if v[j] > vth:
                above += 1
                if v[j] > vtop:
                    top, vtop = j, v[j]
        t += dt
        steps += 1
        if opened:
            pot += slip
        else:
            tot[1] += slip
        if above > 0:
            if not opened:
                opened, t0, pot, hyp, nbl = True, t, 0.0, top, 0
                eid += 1
            for q in range(m):
                j = idx[q]
                if v[j] > vth and stamp[j] != eid:
                    stamp[j] = eid
                    nbl += 1
        elif opened:
            out[0, ne], out[1, ne], out[2, ne], out[3, ne], out[4, ne] = t0, pot, t - t0, hyp, nbl
            ne += 1
            opened = False
        m0 = m
        for q in range(m0):                         # the set grows around every moving block
            j = idx[q]
            if v[j] > 0.0:
                m = _join((j - 1) % n if periodic else max(j - 1, 0), m, idx, inset)
                m = _join((j + 1) % n if periodic else min(j + 1, n - 1), m, idx, inset)
        if m > tot[2]:
            tot[2] = m
        if steps % prune == 0:                      # drop stuck blocks among stuck neighbours
            k = 0
            for q in range(m):
                j = idx[q]
                lf = (j - 1) % n if periodic else max(j - 1, 0)
                rt = (j + 1) % n if periodic else min(j + 1, n - 1)
                if v[j] == 0.0 and v[lf] == 0.0 and v[rt] == 0.0 and \
                        l2 * _lap(u, j, n, periodic) - u[j] + nu * t < 1.0:
                    inset[j] = False
                    s = l2 * _lap(u, j, n, periodic) - u[j] + nu * t
                    t_far = min(t_far, t + (1.0 - s) / nu)
                else:
                    idx[k] = j
                    k += 1
            m = k
    tot[0] += steps
    return ne, t
