"""The compiled chain engine (``bifurcation.chain(..., engine="compiled")``; docs/chain.md, "Engines").

The same model and event algorithm as the heyoka engine (``_loop``), in one numba-compiled loop:

* quiescent phases are jumped exactly (every block stuck: σ grows at rate ν); the largest stress is
  kept in a tournament tree, so finding the next hypocentre costs O(log N), not O(N);
* during an event only a *window* is integrated: the slipping blocks and their chain neighbours, in
  the heyoka engine's per-segment scaled variables (U_j = U_j(t_s) + ν w_j, V_j = ν v_j, a new segment
  at every start), with DOP853 (Hairer's 8th-order pair, ``_dop853``) under a mixed tolerance ``tol``,
  its step by Gustafsson's predictive control (``_segment``: the approach to every stop); for the
  Carlson–Langer law by an order-20 Taylor method instead (``_taylor``: the drop's series by the
  recurrence of 1/(1 + x), the step from the last two terms as heyoka's; 3x fewer steps than DOP853 at
  the same tolerance, its polynomial the dense output);
* every stop (v_j = 0), start of a stuck window block (σ_j = 1) and friction-piece switch is found
  where its event function changes sign over a step and located on the step's 7th-order dense output
  by bracketing root-finding to rounding (the step is then cut there, never at a step boundary); a
  block outside the window is stuck among stuck neighbours and starts at its closed-form time, the
  segment's end; velocity maxima are maximised on the dense output;
* per event the catalog gets an error estimate: the sum over its steps of DOP853's local error
  estimate of the window's displacement (the Taylor series' last term), ν Σ|err(w)|, plus each earlier
  step's velocity error carried over this step (h Σ|err(v)|), relative to the event's potency;
* a block that starts from rest among stuck neighbours (the hypocentre, or a far block that starts
  during the event) follows one stored trajectory (``_lone``: heyoka's Taylor polynomials, computed
  once per run) with no integration, as long as every slipping block of the window is such a lone
  block; at a window block's start the state is handed to DOP853 for the rest of the event.

Memory is O(N) (a few arrays of N entries); the work per event is O(window × steps) plus O(log N)
per block that enters or leaves a window, so it does not grow with N.

Between events, σ_j = s_j + L (L the load added since the last renormalisation, folded into s when it
exceeds 1, an O(N) pass once per loading cycle). During an event, a block outside the window has
σ_j = (s_j − s_h) + 1 + Λ (h the hypocentre, Λ the load added since the event started), so a block
tied with the hypocentre is at σ = 1 exactly, as in the heyoka engine.

The friction drop with the parameter σ_f = ``sigma`` ≥ 0 (docs/chain.md): Φ_σ(x) = (1 − σ_f) Φ(x/(1 − σ_f)),
static threshold 1, so g_σ(x) = σ_f + (1 − σ_f) g(x/(1 − σ_f)).
"""

from __future__ import annotations

import math
from collections import namedtuple
from pathlib import Path

import numba as nb
import numpy as np

from ._numba_cache import CACHE, jit
from numba.extending import overload

from . import _dop853 as _c

__all__ = ["run_events", "tape_eval"]

_A = np.ascontiguousarray(_c.A, dtype=np.float64)
_B = np.ascontiguousarray(_c.B, dtype=np.float64)
_CC = np.ascontiguousarray(_c.C, dtype=np.float64)
_E3 = np.ascontiguousarray(_c.E3, dtype=np.float64)
_E5 = np.ascontiguousarray(_c.E5, dtype=np.float64)
_D = np.ascontiguousarray(_c.D, dtype=np.float64)

# outcome codes of run_events (ChainStatus values where they mean the same)
COMPLETE, NO_STOP, NONFINITE = 1, 3, 5
_NEG_INF = -np.inf


_CACHE = CACHE   # numba has a writable disk cache here (_numba_cache); else compile per process
#: numba checks its disk cache against this file only: also against the files whose numbers or formats the
#: compiled code holds (_numba_cache.jit). _nrt=False: no reference counting (a read of a window array field
#: cost an incref/decref pair; one block start in _rebuild 2.1 µs with it, 0.19 µs without)
_DEPENDS = [Path(__file__).with_name(f"{m}.py") for m in ("_dop853", "_lawtape", "_lone")]
_jit = jit(depends=_DEPENDS, nogil=True, error_model="numpy", _nrt=False)
#: small functions called per block and stage: inlined in numba's IR (a call passed the window's
#: struct of arrays by value: 260 ns per block and right-hand side against 15 inlined)
_inline = jit(depends=_DEPENDS, nogil=True, error_model="numpy", inline="always", _nrt=False)


# -- friction ---------------------------------------------------------------------------------------
@_jit
def tape_eval(code, consts, lo, hi, x, regs):
    """The tape entries [lo, hi) at x; registers are local to the piece (``_lawtape``)."""
    for e in range(lo, hi):
        op = code[e, 0]
        a = code[e, 1] - 0
        b = code[e, 2]
        r = e - lo
        if op == 0:
            regs[r] = x
        elif op == 1:
            regs[r] = consts[e]
        elif op == 2:
            regs[r] = regs[a] + regs[b]
        elif op == 3:
            regs[r] = regs[a] - regs[b]
        elif op == 4:
            regs[r] = regs[a] * regs[b]
        elif op == 5:
            regs[r] = regs[a] / regs[b]
        elif op == 6:
            regs[r] = -regs[a]
        elif op == 7:
            regs[r] = math.exp(regs[a])
        elif op == 8:
            regs[r] = math.log(regs[a])
        elif op == 9:
            regs[r] = math.sqrt(regs[a])
        elif op == 10:
            regs[r] = math.sin(regs[a])
        elif op == 11:
            regs[r] = math.cos(regs[a])
        elif op == 12:
            regs[r] = math.tan(regs[a])
        elif op == 13:
            regs[r] = math.sinh(regs[a])
        elif op == 14:
            regs[r] = math.cosh(regs[a])
        elif op == 15:
            regs[r] = math.tanh(regs[a])
        elif op == 16:
            regs[r] = math.atan(regs[a])
        elif op == 17:
            regs[r] = math.expm1(regs[a])
        elif op == 18:
            regs[r] = math.log1p(regs[a])
        else:
            regs[r] = math.atan2(regs[a], regs[b])
    return regs[hi - lo - 1]


@_jit
def g_carlson_langer(code, consts, tstart, regs, pc, xs):
    """g = x/(1 + x) directly: the benchmark law without the tape (its mere presence in the loop
    cost 45x per block and stage: numba/LLVM then left the stage loop unoptimised)."""
    return xs / (1.0 + xs)


@_jit
def g_tape(code, consts, tstart, regs, pc, xs):
    return tape_eval(code, consts, tstart[pc], tstart[pc + 1], xs, regs)


#: The law's kind, as a type (an empty named tuple) that numba specialises the loop on: ``CarlsonLanger()``
#: or ``Tape()`` (every other law, formulas included). The loop is compiled once per kind and kept in
#: numba's disk cache, so a new process loads it (a whole 10-event CLI run: 0.8 s of CPU) instead of
#: compiling it (8–17 s of CPU per kind, measured on 2 loaded cores).
#: (Passing ``g_carlson_langer`` or ``g_tape`` itself as an argument, a first-class function, made numba
#: refuse the cache: "uses dynamic globals".)
CarlsonLanger = namedtuple("CarlsonLanger", "")
Tape = namedtuple("Tape", "")


def g_law(kind, code, consts, tstart, regs, pc, xs):
    """g(xs) on piece pc: ``g_carlson_langer`` for ``CarlsonLanger()``, else ``g_tape`` (compiled code
    only; numba picks the function when it compiles, from the type of ``kind``)."""
    raise TypeError("g_law is called from compiled code only")


@overload(g_law, jit_options={"cache": _CACHE, "nogil": True, "error_model": "numpy", "_nrt": False})
def _g_law(kind, code, consts, tstart, regs, pc, xs):
    if getattr(kind, "instance_class", None) is CarlsonLanger:
        return lambda kind, code, consts, tstart, regs, pc, xs: g_carlson_langer(code, consts, tstart, regs, pc, xs)
    if getattr(kind, "instance_class", None) is Tape:
        return lambda kind, code, consts, tstart, regs, pc, xs: g_tape(code, consts, tstart, regs, pc, xs)
    return None


@_inline
def _drop(gfun, code, consts, tstart, regs, pc, v, fr):
    """g_σ(x)/ν for a slipping block with scaled velocity v on piece pc (fr: the law's numbers).
    ``gfun`` is the law's kind, ``CarlsonLanger()`` or ``Tape()`` (``g_law``): numba compiles the loop
    once per law kind."""
    sig = fr[2]
    xs = fr[3] * v                    # x/(1 − σ_f) = (ν/ν_f')·v; multiplications, not divisions
    g = g_law(gfun, code, consts, tstart, regs, pc, xs)
    if sig == 0.0:
        return g * fr[4]
    return (sig + (1.0 - sig) * g) * fr[4]


# -- the window's right-hand side -------------------------------------------------------------------
@_inline
def _load(i, w, tau, left, right, selfc, d, l2, nu):
    """(σ − 1)/ν of window slot i: d/ν + ℓ²(coupling) − w + τ (scaled, as ``_integrator``).

    Hot functions take the window's arrays one by one: numba reads a field of a named tuple of
    arrays at ~60 ns (measured: 184 against 8.5 ns per block and right-hand side)."""
    lf, rt = left[i], right[i]
    c = (selfc[i] - 2.0) * w[i]
    if lf >= 0:
        c += w[lf]
    if rt >= 0:
        c += w[rt]
    return d[i] + l2 * c - w[i] + tau     # d here is (σ(t_s) − 1)/ν (win.dn)


@_inline
def _rhs(m, w, v, tau, slip, piece, left, right, selfc, d, gfun, code, consts, tstart, regs, fr, l2, kw, kv, s):
    """Stage s of K (rows of kw, kv indexed here: a row view per call cost ~40 ns)."""
    nu = fr[0]
    for i in range(m):
        if slip[i]:
            kw[i, s] = v[i]
            kv[i, s] = _load(i, w, tau, left, right, selfc, d, l2, nu) + _drop(gfun, code, consts, tstart, regs, piece[i], v[i], fr)
        else:
            kw[i, s] = 0.0
            kv[i, s] = 0.0


@_inline
def _dense(F, y0, i, th):
    """Component i of the step's dense output at θ: DOP853's (``F`` (·, 7) as scipy's Dop853DenseOutput), or
    the Taylor polynomial (``F`` (·, TAYLOR_ORDER): F[i, k − 1] = c_k h^k, ``_taylor``)."""
    if F.shape[1] != 7:
        kk = F.shape[1]
        y = F[i, kk - 1]
        for q in range(kk - 2, -1, -1):
            y = y * th + F[i, q]
        return y0[i] + y * th
    x1 = 1.0 - th
    y = F[i, 6] * th
    y = (y + F[i, 5]) * x1
    y = (y + F[i, 4]) * th
    y = (y + F[i, 3]) * x1
    y = (y + F[i, 2]) * th
    y = (y + F[i, 1]) * x1
    y = (y + F[i, 0]) * th
    return y0[i] + y


@_jit
def _dense_called(F, y0, i, th):
    """``_dense`` called, not inlined: in a start's event function (every inlined ``_root`` held three copies) and
    in the maximisations. With ``_root_called``: the cold compile 42-46 s -> 32-33 s CPU, the same catalog, per
    event within 0.5 % of an unchanged copy timed alongside (N = 64, 256); every ``_dense`` called: 3 % slower."""
    return _dense(F, y0, i, th)


@_inline
def _root8(x):
    """x^(1/8) for the step-size controller by three square roots: libm's pow took ~20 % of a step's time
    (perf, N = 64); equal to x ** 0.125 to within a few ulps, which only moves a step size by as much."""
    return math.sqrt(math.sqrt(math.sqrt(x)))


@_inline   # (a call passed the window's and the law's arrays by value: 1.17x per event at N = 64)
def _step(m, h, tau, win, law, gfun, fr, l2, rtol, atol):
    """One DOP853 step of size h from (win.w, win.v) with K[0] set; fills K[1..12], w1, v1.
    Returns (error norm, Σ|err(w)|). Stuck slots keep their state (K = 0): only slipping ones are
    combined."""
    slip, piece, left, right, selfc, d = win.slip, win.piece, win.left, win.right, win.selfc, win.dn
    code, consts, tstart, regs = law.code, law.consts, law.start, law.regs   # (a named tuple's field: ~400 ns per read)
    kw, kv, tw, tv, w, v, slip = win.kw, win.kv, win.tw, win.tv, win.w, win.v, win.slip
    for i in range(m):
        tw[i] = w[i]
        tv[i] = v[i]
    for s in range(1, 12):
        for i in range(m):
            if slip[i]:
                aw = 0.0
                av = 0.0
                for r in range(s):
                    a = _A[s, r]
                    if a != 0.0:
                        aw += a * kw[i, r]
                        av += a * kv[i, r]
                tw[i] = w[i] + h * aw
                tv[i] = v[i] + h * av
        _rhs(m, tw, tv, tau + _CC[s] * h, slip, piece, left, right, selfc, d, gfun, code, consts, tstart, regs, fr, l2, kw, kv, s)
    w1, v1 = win.w1, win.v1
    e5 = 0.0
    e3 = 0.0
    ew = 0.0
    ev = 0.0
    for i in range(m):
        if not slip[i]:
            w1[i] = w[i]
            v1[i] = v[i]
            continue
        bw = 0.0
        bv = 0.0
        for r in range(12):
            b = _B[r]
            if b != 0.0:
                bw += b * kw[i, r]
                bv += b * kv[i, r]
        w1[i] = w[i] + h * bw
        v1[i] = v[i] + h * bv
    _rhs(m, w1, v1, tau + h, slip, piece, left, right, selfc, d, gfun, code, consts, tstart, regs, fr, l2, kw, kv, 12)
    for i in range(m):
        if not slip[i]:
            continue
        x5w = 0.0
        x3w = 0.0
        x5v = 0.0
        x3v = 0.0
        for r in range(13):
            x5w += _E5[r] * kw[i, r]
            x3w += _E3[r] * kw[i, r]
            x5v += _E5[r] * kv[i, r]
            x3v += _E3[r] * kv[i, r]
        sw = atol + rtol * max(abs(w[i]), abs(w1[i]))
        sv = atol + rtol * max(abs(v[i]), abs(v1[i]))
        a5, b5, a3, b3 = x5w / sw, x5v / sv, x3w / sw, x3v / sv
        e5 += a5 * a5 + b5 * b5
        e3 += a3 * a3 + b3 * b3
        ew += abs(x5w)
        ev += abs(x5v)
    if e5 == 0.0 and e3 == 0.0:
        return 0.0, 0.0, 0.0
    # Hairer's combination of the 5th- and 3rd-order estimates (dop853.f; scipy's DOP853)
    shrink = math.sqrt(e5 / (e5 + 0.01 * e3))
    return abs(h) * math.sqrt(e5) * shrink, abs(h) * ew * shrink, abs(h) * ev * shrink



#: order of the Taylor method of the Carlson–Langer law (``_taylor``): at tol 1e-11 a lone block's event takes
#: 18 steps at order 20 against DOP853's 60 (26 at order 16, 14 at order 24; a step costs ~p²/2 products)
TAYLOR_ORDER = 20


# -- generated by _taylor_gen.source(20): do not edit by hand
@_jit
def _taylor_block(fw, fv, cr, i, sc, c3, amp, l2):
    """Orders 1 … P − 1 of slipping slot i whose neighbours are stuck (their rows zero), order 0 set; sc = selfc[i] − 2."""
    Wa0 = fw[i, 0]
    Va0 = fv[i, 0]
    Ra0 = cr[i, 0]
    k0a = -c3 * Ra0
    kca = l2 * sc - 1.0
    Ra1 = k0a * (Va0 * Ra0)
    Wa1 = Va0 * 0.5
    Va1 = (kca * Wa0 + 1.0 - Ra1 * amp) * 0.5
    Ra2 = k0a * (Va0 * Ra1 + Va1 * Ra0)
    Wa2 = Va1 * 0.3333333333333333
    Va2 = (kca * Wa1 - Ra2 * amp) * 0.3333333333333333
    Ra3 = k0a * (Va1 * Ra1 + Va0 * Ra2 + Va2 * Ra0)
    Wa3 = Va2 * 0.25
    Va3 = (kca * Wa2 - Ra3 * amp) * 0.25
    Ra4 = k0a * (Va1 * Ra2 + Va2 * Ra1 + Va0 * Ra3 + Va3 * Ra0)
    Wa4 = Va3 * 0.2
    Va4 = (kca * Wa3 - Ra4 * amp) * 0.2
    Ra5 = k0a * (Va1 * Ra3 + Va2 * Ra2 + Va3 * Ra1 + Va0 * Ra4 + Va4 * Ra0)
    Wa5 = Va4 * 0.16666666666666666
    Va5 = (kca * Wa4 - Ra5 * amp) * 0.16666666666666666
    Ra6 = k0a * (Va1 * Ra4 + Va2 * Ra3 + Va3 * Ra2 + Va4 * Ra1 + Va0 * Ra5 + Va5 * Ra0)
    Wa6 = Va5 * 0.14285714285714285
    Va6 = (kca * Wa5 - Ra6 * amp) * 0.14285714285714285
    Ra7 = k0a * (Va1 * Ra5 + Va2 * Ra4 + Va3 * Ra3 + Va4 * Ra2 + Va5 * Ra1 + Va0 * Ra6 + Va6 * Ra0)
    Wa7 = Va6 * 0.125
    Va7 = (kca * Wa6 - Ra7 * amp) * 0.125
    Ra8 = k0a * (Va1 * Ra6 + Va2 * Ra5 + Va3 * Ra4 + Va4 * Ra3 + Va5 * Ra2 + Va6 * Ra1 + Va0 * Ra7 + Va7 * Ra0)
    Wa8 = Va7 * 0.1111111111111111
    Va8 = (kca * Wa7 - Ra8 * amp) * 0.1111111111111111
    Ra9 = k0a * (Va1 * Ra7 + Va2 * Ra6 + Va3 * Ra5 + Va4 * Ra4 + Va5 * Ra3 + Va6 * Ra2 + Va7 * Ra1 + Va0 * Ra8 + Va8 * Ra0)
    Wa9 = Va8 * 0.1
    Va9 = (kca * Wa8 - Ra9 * amp) * 0.1
    Ra10 = k0a * (Va1 * Ra8 + Va2 * Ra7 + Va3 * Ra6 + Va4 * Ra5 + Va5 * Ra4 + Va6 * Ra3 + Va7 * Ra2 + Va8 * Ra1 + Va0 * Ra9 + Va9 * Ra0)
    Wa10 = Va9 * 0.09090909090909091
    Va10 = (kca * Wa9 - Ra10 * amp) * 0.09090909090909091
    Ra11 = k0a * (Va1 * Ra9 + Va2 * Ra8 + Va3 * Ra7 + Va4 * Ra6 + Va5 * Ra5 + Va6 * Ra4 + Va7 * Ra3 + Va8 * Ra2 + Va9 * Ra1 + Va0 * Ra10 + Va10 * Ra0)
    Wa11 = Va10 * 0.08333333333333333
    Va11 = (kca * Wa10 - Ra11 * amp) * 0.08333333333333333
    Ra12 = k0a * (Va1 * Ra10 + Va2 * Ra9 + Va3 * Ra8 + Va4 * Ra7 + Va5 * Ra6 + Va6 * Ra5 + Va7 * Ra4 + Va8 * Ra3 + Va9 * Ra2 + Va10 * Ra1 + Va0 * Ra11 + Va11 * Ra0)
    Wa12 = Va11 * 0.07692307692307693
    Va12 = (kca * Wa11 - Ra12 * amp) * 0.07692307692307693
    Ra13 = k0a * (Va1 * Ra11 + Va2 * Ra10 + Va3 * Ra9 + Va4 * Ra8 + Va5 * Ra7 + Va6 * Ra6 + Va7 * Ra5 + Va8 * Ra4 + Va9 * Ra3 + Va10 * Ra2 + Va11 * Ra1 + Va0 * Ra12 + Va12 * Ra0)
    Wa13 = Va12 * 0.07142857142857142
    Va13 = (kca * Wa12 - Ra13 * amp) * 0.07142857142857142
    Ra14 = k0a * (Va1 * Ra12 + Va2 * Ra11 + Va3 * Ra10 + Va4 * Ra9 + Va5 * Ra8 + Va6 * Ra7 + Va7 * Ra6 + Va8 * Ra5 + Va9 * Ra4 + Va10 * Ra3 + Va11 * Ra2 + Va12 * Ra1 + Va0 * Ra13 + Va13 * Ra0)
    Wa14 = Va13 * 0.06666666666666667
    Va14 = (kca * Wa13 - Ra14 * amp) * 0.06666666666666667
    Ra15 = k0a * (Va1 * Ra13 + Va2 * Ra12 + Va3 * Ra11 + Va4 * Ra10 + Va5 * Ra9 + Va6 * Ra8 + Va7 * Ra7 + Va8 * Ra6 + Va9 * Ra5 + Va10 * Ra4 + Va11 * Ra3 + Va12 * Ra2 + Va13 * Ra1 + Va0 * Ra14 + Va14 * Ra0)
    Wa15 = Va14 * 0.0625
    Va15 = (kca * Wa14 - Ra15 * amp) * 0.0625
    Ra16 = k0a * (Va1 * Ra14 + Va2 * Ra13 + Va3 * Ra12 + Va4 * Ra11 + Va5 * Ra10 + Va6 * Ra9 + Va7 * Ra8 + Va8 * Ra7 + Va9 * Ra6 + Va10 * Ra5 + Va11 * Ra4 + Va12 * Ra3 + Va13 * Ra2 + Va14 * Ra1 + Va0 * Ra15 + Va15 * Ra0)
    Wa16 = Va15 * 0.058823529411764705
    Va16 = (kca * Wa15 - Ra16 * amp) * 0.058823529411764705
    Ra17 = k0a * (Va1 * Ra15 + Va2 * Ra14 + Va3 * Ra13 + Va4 * Ra12 + Va5 * Ra11 + Va6 * Ra10 + Va7 * Ra9 + Va8 * Ra8 + Va9 * Ra7 + Va10 * Ra6 + Va11 * Ra5 + Va12 * Ra4 + Va13 * Ra3 + Va14 * Ra2 + Va15 * Ra1 + Va0 * Ra16 + Va16 * Ra0)
    Wa17 = Va16 * 0.05555555555555555
    Va17 = (kca * Wa16 - Ra17 * amp) * 0.05555555555555555
    Ra18 = k0a * (Va1 * Ra16 + Va2 * Ra15 + Va3 * Ra14 + Va4 * Ra13 + Va5 * Ra12 + Va6 * Ra11 + Va7 * Ra10 + Va8 * Ra9 + Va9 * Ra8 + Va10 * Ra7 + Va11 * Ra6 + Va12 * Ra5 + Va13 * Ra4 + Va14 * Ra3 + Va15 * Ra2 + Va16 * Ra1 + Va0 * Ra17 + Va17 * Ra0)
    Wa18 = Va17 * 0.05263157894736842
    Va18 = (kca * Wa17 - Ra18 * amp) * 0.05263157894736842
    Ra19 = k0a * (Va1 * Ra17 + Va2 * Ra16 + Va3 * Ra15 + Va4 * Ra14 + Va5 * Ra13 + Va6 * Ra12 + Va7 * Ra11 + Va8 * Ra10 + Va9 * Ra9 + Va10 * Ra8 + Va11 * Ra7 + Va12 * Ra6 + Va13 * Ra5 + Va14 * Ra4 + Va15 * Ra3 + Va16 * Ra2 + Va17 * Ra1 + Va0 * Ra18 + Va18 * Ra0)
    Wa19 = Va18 * 0.05
    Va19 = (kca * Wa18 - Ra19 * amp) * 0.05
    fw[i, 1], fv[i, 1], cr[i, 1] = Wa1, Va1, Ra1
    fw[i, 2], fv[i, 2], cr[i, 2] = Wa2, Va2, Ra2
    fw[i, 3], fv[i, 3], cr[i, 3] = Wa3, Va3, Ra3
    fw[i, 4], fv[i, 4], cr[i, 4] = Wa4, Va4, Ra4
    fw[i, 5], fv[i, 5], cr[i, 5] = Wa5, Va5, Ra5
    fw[i, 6], fv[i, 6], cr[i, 6] = Wa6, Va6, Ra6
    fw[i, 7], fv[i, 7], cr[i, 7] = Wa7, Va7, Ra7
    fw[i, 8], fv[i, 8], cr[i, 8] = Wa8, Va8, Ra8
    fw[i, 9], fv[i, 9], cr[i, 9] = Wa9, Va9, Ra9
    fw[i, 10], fv[i, 10], cr[i, 10] = Wa10, Va10, Ra10
    fw[i, 11], fv[i, 11], cr[i, 11] = Wa11, Va11, Ra11
    fw[i, 12], fv[i, 12], cr[i, 12] = Wa12, Va12, Ra12
    fw[i, 13], fv[i, 13], cr[i, 13] = Wa13, Va13, Ra13
    fw[i, 14], fv[i, 14], cr[i, 14] = Wa14, Va14, Ra14
    fw[i, 15], fv[i, 15], cr[i, 15] = Wa15, Va15, Ra15
    fw[i, 16], fv[i, 16], cr[i, 16] = Wa16, Va16, Ra16
    fw[i, 17], fv[i, 17], cr[i, 17] = Wa17, Va17, Ra17
    fw[i, 18], fv[i, 18], cr[i, 18] = Wa18, Va18, Ra18
    fw[i, 19], fv[i, 19], cr[i, 19] = Wa19, Va19, Ra19


@_jit
def _taylor_pair(fw, fv, cr, i, j, sci, scj, c3, amp, l2):
    """Orders 1 … P − 1 of adjacent slipping slots i and j whose other neighbours are stuck."""
    Wa0 = fw[i, 0]
    Va0 = fv[i, 0]
    Ra0 = cr[i, 0]
    k0a = -c3 * Ra0
    kca = l2 * sci - 1.0
    Wb0 = fw[j, 0]
    Vb0 = fv[j, 0]
    Rb0 = cr[j, 0]
    k0b = -c3 * Rb0
    kcb = l2 * scj - 1.0
    Ra1 = k0a * (Va0 * Ra0)
    Wa1 = Va0 * 0.5
    Va1 = (kca * Wa0 + l2 * Wb0 + 1.0 - Ra1 * amp) * 0.5
    Rb1 = k0b * (Vb0 * Rb0)
    Wb1 = Vb0 * 0.5
    Vb1 = (kcb * Wb0 + l2 * Wa0 + 1.0 - Rb1 * amp) * 0.5
    Ra2 = k0a * (Va0 * Ra1 + Va1 * Ra0)
    Wa2 = Va1 * 0.3333333333333333
    Va2 = (kca * Wa1 + l2 * Wb1 - Ra2 * amp) * 0.3333333333333333
    Rb2 = k0b * (Vb0 * Rb1 + Vb1 * Rb0)
    Wb2 = Vb1 * 0.3333333333333333
    Vb2 = (kcb * Wb1 + l2 * Wa1 - Rb2 * amp) * 0.3333333333333333
    Ra3 = k0a * (Va1 * Ra1 + Va0 * Ra2 + Va2 * Ra0)
    Wa3 = Va2 * 0.25
    Va3 = (kca * Wa2 + l2 * Wb2 - Ra3 * amp) * 0.25
    Rb3 = k0b * (Vb1 * Rb1 + Vb0 * Rb2 + Vb2 * Rb0)
    Wb3 = Vb2 * 0.25
    Vb3 = (kcb * Wb2 + l2 * Wa2 - Rb3 * amp) * 0.25
    Ra4 = k0a * (Va1 * Ra2 + Va2 * Ra1 + Va0 * Ra3 + Va3 * Ra0)
    Wa4 = Va3 * 0.2
    Va4 = (kca * Wa3 + l2 * Wb3 - Ra4 * amp) * 0.2
    Rb4 = k0b * (Vb1 * Rb2 + Vb2 * Rb1 + Vb0 * Rb3 + Vb3 * Rb0)
    Wb4 = Vb3 * 0.2
    Vb4 = (kcb * Wb3 + l2 * Wa3 - Rb4 * amp) * 0.2
    Ra5 = k0a * (Va1 * Ra3 + Va2 * Ra2 + Va3 * Ra1 + Va0 * Ra4 + Va4 * Ra0)
    Wa5 = Va4 * 0.16666666666666666
    Va5 = (kca * Wa4 + l2 * Wb4 - Ra5 * amp) * 0.16666666666666666
    Rb5 = k0b * (Vb1 * Rb3 + Vb2 * Rb2 + Vb3 * Rb1 + Vb0 * Rb4 + Vb4 * Rb0)
    Wb5 = Vb4 * 0.16666666666666666
    Vb5 = (kcb * Wb4 + l2 * Wa4 - Rb5 * amp) * 0.16666666666666666
    Ra6 = k0a * (Va1 * Ra4 + Va2 * Ra3 + Va3 * Ra2 + Va4 * Ra1 + Va0 * Ra5 + Va5 * Ra0)
    Wa6 = Va5 * 0.14285714285714285
    Va6 = (kca * Wa5 + l2 * Wb5 - Ra6 * amp) * 0.14285714285714285
    Rb6 = k0b * (Vb1 * Rb4 + Vb2 * Rb3 + Vb3 * Rb2 + Vb4 * Rb1 + Vb0 * Rb5 + Vb5 * Rb0)
    Wb6 = Vb5 * 0.14285714285714285
    Vb6 = (kcb * Wb5 + l2 * Wa5 - Rb6 * amp) * 0.14285714285714285
    Ra7 = k0a * (Va1 * Ra5 + Va2 * Ra4 + Va3 * Ra3 + Va4 * Ra2 + Va5 * Ra1 + Va0 * Ra6 + Va6 * Ra0)
    Wa7 = Va6 * 0.125
    Va7 = (kca * Wa6 + l2 * Wb6 - Ra7 * amp) * 0.125
    Rb7 = k0b * (Vb1 * Rb5 + Vb2 * Rb4 + Vb3 * Rb3 + Vb4 * Rb2 + Vb5 * Rb1 + Vb0 * Rb6 + Vb6 * Rb0)
    Wb7 = Vb6 * 0.125
    Vb7 = (kcb * Wb6 + l2 * Wa6 - Rb7 * amp) * 0.125
    Ra8 = k0a * (Va1 * Ra6 + Va2 * Ra5 + Va3 * Ra4 + Va4 * Ra3 + Va5 * Ra2 + Va6 * Ra1 + Va0 * Ra7 + Va7 * Ra0)
    Wa8 = Va7 * 0.1111111111111111
    Va8 = (kca * Wa7 + l2 * Wb7 - Ra8 * amp) * 0.1111111111111111
    Rb8 = k0b * (Vb1 * Rb6 + Vb2 * Rb5 + Vb3 * Rb4 + Vb4 * Rb3 + Vb5 * Rb2 + Vb6 * Rb1 + Vb0 * Rb7 + Vb7 * Rb0)
    Wb8 = Vb7 * 0.1111111111111111
    Vb8 = (kcb * Wb7 + l2 * Wa7 - Rb8 * amp) * 0.1111111111111111
    Ra9 = k0a * (Va1 * Ra7 + Va2 * Ra6 + Va3 * Ra5 + Va4 * Ra4 + Va5 * Ra3 + Va6 * Ra2 + Va7 * Ra1 + Va0 * Ra8 + Va8 * Ra0)
    Wa9 = Va8 * 0.1
    Va9 = (kca * Wa8 + l2 * Wb8 - Ra9 * amp) * 0.1
    Rb9 = k0b * (Vb1 * Rb7 + Vb2 * Rb6 + Vb3 * Rb5 + Vb4 * Rb4 + Vb5 * Rb3 + Vb6 * Rb2 + Vb7 * Rb1 + Vb0 * Rb8 + Vb8 * Rb0)
    Wb9 = Vb8 * 0.1
    Vb9 = (kcb * Wb8 + l2 * Wa8 - Rb9 * amp) * 0.1
    Ra10 = k0a * (Va1 * Ra8 + Va2 * Ra7 + Va3 * Ra6 + Va4 * Ra5 + Va5 * Ra4 + Va6 * Ra3 + Va7 * Ra2 + Va8 * Ra1 + Va0 * Ra9 + Va9 * Ra0)
    Wa10 = Va9 * 0.09090909090909091
    Va10 = (kca * Wa9 + l2 * Wb9 - Ra10 * amp) * 0.09090909090909091
    Rb10 = k0b * (Vb1 * Rb8 + Vb2 * Rb7 + Vb3 * Rb6 + Vb4 * Rb5 + Vb5 * Rb4 + Vb6 * Rb3 + Vb7 * Rb2 + Vb8 * Rb1 + Vb0 * Rb9 + Vb9 * Rb0)
    Wb10 = Vb9 * 0.09090909090909091
    Vb10 = (kcb * Wb9 + l2 * Wa9 - Rb10 * amp) * 0.09090909090909091
    Ra11 = k0a * (Va1 * Ra9 + Va2 * Ra8 + Va3 * Ra7 + Va4 * Ra6 + Va5 * Ra5 + Va6 * Ra4 + Va7 * Ra3 + Va8 * Ra2 + Va9 * Ra1 + Va0 * Ra10 + Va10 * Ra0)
    Wa11 = Va10 * 0.08333333333333333
    Va11 = (kca * Wa10 + l2 * Wb10 - Ra11 * amp) * 0.08333333333333333
    Rb11 = k0b * (Vb1 * Rb9 + Vb2 * Rb8 + Vb3 * Rb7 + Vb4 * Rb6 + Vb5 * Rb5 + Vb6 * Rb4 + Vb7 * Rb3 + Vb8 * Rb2 + Vb9 * Rb1 + Vb0 * Rb10 + Vb10 * Rb0)
    Wb11 = Vb10 * 0.08333333333333333
    Vb11 = (kcb * Wb10 + l2 * Wa10 - Rb11 * amp) * 0.08333333333333333
    Ra12 = k0a * (Va1 * Ra10 + Va2 * Ra9 + Va3 * Ra8 + Va4 * Ra7 + Va5 * Ra6 + Va6 * Ra5 + Va7 * Ra4 + Va8 * Ra3 + Va9 * Ra2 + Va10 * Ra1 + Va0 * Ra11 + Va11 * Ra0)
    Wa12 = Va11 * 0.07692307692307693
    Va12 = (kca * Wa11 + l2 * Wb11 - Ra12 * amp) * 0.07692307692307693
    Rb12 = k0b * (Vb1 * Rb10 + Vb2 * Rb9 + Vb3 * Rb8 + Vb4 * Rb7 + Vb5 * Rb6 + Vb6 * Rb5 + Vb7 * Rb4 + Vb8 * Rb3 + Vb9 * Rb2 + Vb10 * Rb1 + Vb0 * Rb11 + Vb11 * Rb0)
    Wb12 = Vb11 * 0.07692307692307693
    Vb12 = (kcb * Wb11 + l2 * Wa11 - Rb12 * amp) * 0.07692307692307693
    Ra13 = k0a * (Va1 * Ra11 + Va2 * Ra10 + Va3 * Ra9 + Va4 * Ra8 + Va5 * Ra7 + Va6 * Ra6 + Va7 * Ra5 + Va8 * Ra4 + Va9 * Ra3 + Va10 * Ra2 + Va11 * Ra1 + Va0 * Ra12 + Va12 * Ra0)
    Wa13 = Va12 * 0.07142857142857142
    Va13 = (kca * Wa12 + l2 * Wb12 - Ra13 * amp) * 0.07142857142857142
    Rb13 = k0b * (Vb1 * Rb11 + Vb2 * Rb10 + Vb3 * Rb9 + Vb4 * Rb8 + Vb5 * Rb7 + Vb6 * Rb6 + Vb7 * Rb5 + Vb8 * Rb4 + Vb9 * Rb3 + Vb10 * Rb2 + Vb11 * Rb1 + Vb0 * Rb12 + Vb12 * Rb0)
    Wb13 = Vb12 * 0.07142857142857142
    Vb13 = (kcb * Wb12 + l2 * Wa12 - Rb13 * amp) * 0.07142857142857142
    Ra14 = k0a * (Va1 * Ra12 + Va2 * Ra11 + Va3 * Ra10 + Va4 * Ra9 + Va5 * Ra8 + Va6 * Ra7 + Va7 * Ra6 + Va8 * Ra5 + Va9 * Ra4 + Va10 * Ra3 + Va11 * Ra2 + Va12 * Ra1 + Va0 * Ra13 + Va13 * Ra0)
    Wa14 = Va13 * 0.06666666666666667
    Va14 = (kca * Wa13 + l2 * Wb13 - Ra14 * amp) * 0.06666666666666667
    Rb14 = k0b * (Vb1 * Rb12 + Vb2 * Rb11 + Vb3 * Rb10 + Vb4 * Rb9 + Vb5 * Rb8 + Vb6 * Rb7 + Vb7 * Rb6 + Vb8 * Rb5 + Vb9 * Rb4 + Vb10 * Rb3 + Vb11 * Rb2 + Vb12 * Rb1 + Vb0 * Rb13 + Vb13 * Rb0)
    Wb14 = Vb13 * 0.06666666666666667
    Vb14 = (kcb * Wb13 + l2 * Wa13 - Rb14 * amp) * 0.06666666666666667
    Ra15 = k0a * (Va1 * Ra13 + Va2 * Ra12 + Va3 * Ra11 + Va4 * Ra10 + Va5 * Ra9 + Va6 * Ra8 + Va7 * Ra7 + Va8 * Ra6 + Va9 * Ra5 + Va10 * Ra4 + Va11 * Ra3 + Va12 * Ra2 + Va13 * Ra1 + Va0 * Ra14 + Va14 * Ra0)
    Wa15 = Va14 * 0.0625
    Va15 = (kca * Wa14 + l2 * Wb14 - Ra15 * amp) * 0.0625
    Rb15 = k0b * (Vb1 * Rb13 + Vb2 * Rb12 + Vb3 * Rb11 + Vb4 * Rb10 + Vb5 * Rb9 + Vb6 * Rb8 + Vb7 * Rb7 + Vb8 * Rb6 + Vb9 * Rb5 + Vb10 * Rb4 + Vb11 * Rb3 + Vb12 * Rb2 + Vb13 * Rb1 + Vb0 * Rb14 + Vb14 * Rb0)
    Wb15 = Vb14 * 0.0625
    Vb15 = (kcb * Wb14 + l2 * Wa14 - Rb15 * amp) * 0.0625
    Ra16 = k0a * (Va1 * Ra14 + Va2 * Ra13 + Va3 * Ra12 + Va4 * Ra11 + Va5 * Ra10 + Va6 * Ra9 + Va7 * Ra8 + Va8 * Ra7 + Va9 * Ra6 + Va10 * Ra5 + Va11 * Ra4 + Va12 * Ra3 + Va13 * Ra2 + Va14 * Ra1 + Va0 * Ra15 + Va15 * Ra0)
    Wa16 = Va15 * 0.058823529411764705
    Va16 = (kca * Wa15 + l2 * Wb15 - Ra16 * amp) * 0.058823529411764705
    Rb16 = k0b * (Vb1 * Rb14 + Vb2 * Rb13 + Vb3 * Rb12 + Vb4 * Rb11 + Vb5 * Rb10 + Vb6 * Rb9 + Vb7 * Rb8 + Vb8 * Rb7 + Vb9 * Rb6 + Vb10 * Rb5 + Vb11 * Rb4 + Vb12 * Rb3 + Vb13 * Rb2 + Vb14 * Rb1 + Vb0 * Rb15 + Vb15 * Rb0)
    Wb16 = Vb15 * 0.058823529411764705
    Vb16 = (kcb * Wb15 + l2 * Wa15 - Rb16 * amp) * 0.058823529411764705
    Ra17 = k0a * (Va1 * Ra15 + Va2 * Ra14 + Va3 * Ra13 + Va4 * Ra12 + Va5 * Ra11 + Va6 * Ra10 + Va7 * Ra9 + Va8 * Ra8 + Va9 * Ra7 + Va10 * Ra6 + Va11 * Ra5 + Va12 * Ra4 + Va13 * Ra3 + Va14 * Ra2 + Va15 * Ra1 + Va0 * Ra16 + Va16 * Ra0)
    Wa17 = Va16 * 0.05555555555555555
    Va17 = (kca * Wa16 + l2 * Wb16 - Ra17 * amp) * 0.05555555555555555
    Rb17 = k0b * (Vb1 * Rb15 + Vb2 * Rb14 + Vb3 * Rb13 + Vb4 * Rb12 + Vb5 * Rb11 + Vb6 * Rb10 + Vb7 * Rb9 + Vb8 * Rb8 + Vb9 * Rb7 + Vb10 * Rb6 + Vb11 * Rb5 + Vb12 * Rb4 + Vb13 * Rb3 + Vb14 * Rb2 + Vb15 * Rb1 + Vb0 * Rb16 + Vb16 * Rb0)
    Wb17 = Vb16 * 0.05555555555555555
    Vb17 = (kcb * Wb16 + l2 * Wa16 - Rb17 * amp) * 0.05555555555555555
    Ra18 = k0a * (Va1 * Ra16 + Va2 * Ra15 + Va3 * Ra14 + Va4 * Ra13 + Va5 * Ra12 + Va6 * Ra11 + Va7 * Ra10 + Va8 * Ra9 + Va9 * Ra8 + Va10 * Ra7 + Va11 * Ra6 + Va12 * Ra5 + Va13 * Ra4 + Va14 * Ra3 + Va15 * Ra2 + Va16 * Ra1 + Va0 * Ra17 + Va17 * Ra0)
    Wa18 = Va17 * 0.05263157894736842
    Va18 = (kca * Wa17 + l2 * Wb17 - Ra18 * amp) * 0.05263157894736842
    Rb18 = k0b * (Vb1 * Rb16 + Vb2 * Rb15 + Vb3 * Rb14 + Vb4 * Rb13 + Vb5 * Rb12 + Vb6 * Rb11 + Vb7 * Rb10 + Vb8 * Rb9 + Vb9 * Rb8 + Vb10 * Rb7 + Vb11 * Rb6 + Vb12 * Rb5 + Vb13 * Rb4 + Vb14 * Rb3 + Vb15 * Rb2 + Vb16 * Rb1 + Vb0 * Rb17 + Vb17 * Rb0)
    Wb18 = Vb17 * 0.05263157894736842
    Vb18 = (kcb * Wb17 + l2 * Wa17 - Rb18 * amp) * 0.05263157894736842
    Ra19 = k0a * (Va1 * Ra17 + Va2 * Ra16 + Va3 * Ra15 + Va4 * Ra14 + Va5 * Ra13 + Va6 * Ra12 + Va7 * Ra11 + Va8 * Ra10 + Va9 * Ra9 + Va10 * Ra8 + Va11 * Ra7 + Va12 * Ra6 + Va13 * Ra5 + Va14 * Ra4 + Va15 * Ra3 + Va16 * Ra2 + Va17 * Ra1 + Va0 * Ra18 + Va18 * Ra0)
    Wa19 = Va18 * 0.05
    Va19 = (kca * Wa18 + l2 * Wb18 - Ra19 * amp) * 0.05
    Rb19 = k0b * (Vb1 * Rb17 + Vb2 * Rb16 + Vb3 * Rb15 + Vb4 * Rb14 + Vb5 * Rb13 + Vb6 * Rb12 + Vb7 * Rb11 + Vb8 * Rb10 + Vb9 * Rb9 + Vb10 * Rb8 + Vb11 * Rb7 + Vb12 * Rb6 + Vb13 * Rb5 + Vb14 * Rb4 + Vb15 * Rb3 + Vb16 * Rb2 + Vb17 * Rb1 + Vb0 * Rb18 + Vb18 * Rb0)
    Wb19 = Vb18 * 0.05
    Vb19 = (kcb * Wb18 + l2 * Wa18 - Rb19 * amp) * 0.05
    fw[i, 1], fv[i, 1], cr[i, 1] = Wa1, Va1, Ra1
    fw[j, 1], fv[j, 1], cr[j, 1] = Wb1, Vb1, Rb1
    fw[i, 2], fv[i, 2], cr[i, 2] = Wa2, Va2, Ra2
    fw[j, 2], fv[j, 2], cr[j, 2] = Wb2, Vb2, Rb2
    fw[i, 3], fv[i, 3], cr[i, 3] = Wa3, Va3, Ra3
    fw[j, 3], fv[j, 3], cr[j, 3] = Wb3, Vb3, Rb3
    fw[i, 4], fv[i, 4], cr[i, 4] = Wa4, Va4, Ra4
    fw[j, 4], fv[j, 4], cr[j, 4] = Wb4, Vb4, Rb4
    fw[i, 5], fv[i, 5], cr[i, 5] = Wa5, Va5, Ra5
    fw[j, 5], fv[j, 5], cr[j, 5] = Wb5, Vb5, Rb5
    fw[i, 6], fv[i, 6], cr[i, 6] = Wa6, Va6, Ra6
    fw[j, 6], fv[j, 6], cr[j, 6] = Wb6, Vb6, Rb6
    fw[i, 7], fv[i, 7], cr[i, 7] = Wa7, Va7, Ra7
    fw[j, 7], fv[j, 7], cr[j, 7] = Wb7, Vb7, Rb7
    fw[i, 8], fv[i, 8], cr[i, 8] = Wa8, Va8, Ra8
    fw[j, 8], fv[j, 8], cr[j, 8] = Wb8, Vb8, Rb8
    fw[i, 9], fv[i, 9], cr[i, 9] = Wa9, Va9, Ra9
    fw[j, 9], fv[j, 9], cr[j, 9] = Wb9, Vb9, Rb9
    fw[i, 10], fv[i, 10], cr[i, 10] = Wa10, Va10, Ra10
    fw[j, 10], fv[j, 10], cr[j, 10] = Wb10, Vb10, Rb10
    fw[i, 11], fv[i, 11], cr[i, 11] = Wa11, Va11, Ra11
    fw[j, 11], fv[j, 11], cr[j, 11] = Wb11, Vb11, Rb11
    fw[i, 12], fv[i, 12], cr[i, 12] = Wa12, Va12, Ra12
    fw[j, 12], fv[j, 12], cr[j, 12] = Wb12, Vb12, Rb12
    fw[i, 13], fv[i, 13], cr[i, 13] = Wa13, Va13, Ra13
    fw[j, 13], fv[j, 13], cr[j, 13] = Wb13, Vb13, Rb13
    fw[i, 14], fv[i, 14], cr[i, 14] = Wa14, Va14, Ra14
    fw[j, 14], fv[j, 14], cr[j, 14] = Wb14, Vb14, Rb14
    fw[i, 15], fv[i, 15], cr[i, 15] = Wa15, Va15, Ra15
    fw[j, 15], fv[j, 15], cr[j, 15] = Wb15, Vb15, Rb15
    fw[i, 16], fv[i, 16], cr[i, 16] = Wa16, Va16, Ra16
    fw[j, 16], fv[j, 16], cr[j, 16] = Wb16, Vb16, Rb16
    fw[i, 17], fv[i, 17], cr[i, 17] = Wa17, Va17, Ra17
    fw[j, 17], fv[j, 17], cr[j, 17] = Wb17, Vb17, Rb17
    fw[i, 18], fv[i, 18], cr[i, 18] = Wa18, Va18, Ra18
    fw[j, 18], fv[j, 18], cr[j, 18] = Wb18, Vb18, Rb18
    fw[i, 19], fv[i, 19], cr[i, 19] = Wa19, Va19, Ra19
    fw[j, 19], fv[j, 19], cr[j, 19] = Wb19, Vb19, Rb19


@_jit
def _taylor_triple(fw, fv, cr, i, j, k, sci, scj, sck, c3, amp, l2):
    """Orders 1 … P − 1 of three slipping slots i, j, k in a row (j between) whose other neighbours are stuck."""
    Wa0 = fw[i, 0]
    Va0 = fv[i, 0]
    Ra0 = cr[i, 0]
    k0a = -c3 * Ra0
    kca = l2 * sci - 1.0
    Wb0 = fw[j, 0]
    Vb0 = fv[j, 0]
    Rb0 = cr[j, 0]
    k0b = -c3 * Rb0
    kcb = l2 * scj - 1.0
    Wc0 = fw[k, 0]
    Vc0 = fv[k, 0]
    Rc0 = cr[k, 0]
    k0c = -c3 * Rc0
    kcc = l2 * sck - 1.0
    Ra1 = k0a * (Va0 * Ra0)
    Wa1 = Va0 * 0.5
    Va1 = (kca * Wa0 + l2 * Wb0 + 1.0 - Ra1 * amp) * 0.5
    Rb1 = k0b * (Vb0 * Rb0)
    Wb1 = Vb0 * 0.5
    Vb1 = (kcb * Wb0 + l2 * (Wa0 + Wc0) + 1.0 - Rb1 * amp) * 0.5
    Rc1 = k0c * (Vc0 * Rc0)
    Wc1 = Vc0 * 0.5
    Vc1 = (kcc * Wc0 + l2 * Wb0 + 1.0 - Rc1 * amp) * 0.5
    Ra2 = k0a * (Va0 * Ra1 + Va1 * Ra0)
    Wa2 = Va1 * 0.3333333333333333
    Va2 = (kca * Wa1 + l2 * Wb1 - Ra2 * amp) * 0.3333333333333333
    Rb2 = k0b * (Vb0 * Rb1 + Vb1 * Rb0)
    Wb2 = Vb1 * 0.3333333333333333
    Vb2 = (kcb * Wb1 + l2 * (Wa1 + Wc1) - Rb2 * amp) * 0.3333333333333333
    Rc2 = k0c * (Vc0 * Rc1 + Vc1 * Rc0)
    Wc2 = Vc1 * 0.3333333333333333
    Vc2 = (kcc * Wc1 + l2 * Wb1 - Rc2 * amp) * 0.3333333333333333
    Ra3 = k0a * (Va1 * Ra1 + Va0 * Ra2 + Va2 * Ra0)
    Wa3 = Va2 * 0.25
    Va3 = (kca * Wa2 + l2 * Wb2 - Ra3 * amp) * 0.25
    Rb3 = k0b * (Vb1 * Rb1 + Vb0 * Rb2 + Vb2 * Rb0)
    Wb3 = Vb2 * 0.25
    Vb3 = (kcb * Wb2 + l2 * (Wa2 + Wc2) - Rb3 * amp) * 0.25
    Rc3 = k0c * (Vc1 * Rc1 + Vc0 * Rc2 + Vc2 * Rc0)
    Wc3 = Vc2 * 0.25
    Vc3 = (kcc * Wc2 + l2 * Wb2 - Rc3 * amp) * 0.25
    Ra4 = k0a * (Va1 * Ra2 + Va2 * Ra1 + Va0 * Ra3 + Va3 * Ra0)
    Wa4 = Va3 * 0.2
    Va4 = (kca * Wa3 + l2 * Wb3 - Ra4 * amp) * 0.2
    Rb4 = k0b * (Vb1 * Rb2 + Vb2 * Rb1 + Vb0 * Rb3 + Vb3 * Rb0)
    Wb4 = Vb3 * 0.2
    Vb4 = (kcb * Wb3 + l2 * (Wa3 + Wc3) - Rb4 * amp) * 0.2
    Rc4 = k0c * (Vc1 * Rc2 + Vc2 * Rc1 + Vc0 * Rc3 + Vc3 * Rc0)
    Wc4 = Vc3 * 0.2
    Vc4 = (kcc * Wc3 + l2 * Wb3 - Rc4 * amp) * 0.2
    Ra5 = k0a * (Va1 * Ra3 + Va2 * Ra2 + Va3 * Ra1 + Va0 * Ra4 + Va4 * Ra0)
    Wa5 = Va4 * 0.16666666666666666
    Va5 = (kca * Wa4 + l2 * Wb4 - Ra5 * amp) * 0.16666666666666666
    Rb5 = k0b * (Vb1 * Rb3 + Vb2 * Rb2 + Vb3 * Rb1 + Vb0 * Rb4 + Vb4 * Rb0)
    Wb5 = Vb4 * 0.16666666666666666
    Vb5 = (kcb * Wb4 + l2 * (Wa4 + Wc4) - Rb5 * amp) * 0.16666666666666666
    Rc5 = k0c * (Vc1 * Rc3 + Vc2 * Rc2 + Vc3 * Rc1 + Vc0 * Rc4 + Vc4 * Rc0)
    Wc5 = Vc4 * 0.16666666666666666
    Vc5 = (kcc * Wc4 + l2 * Wb4 - Rc5 * amp) * 0.16666666666666666
    Ra6 = k0a * (Va1 * Ra4 + Va2 * Ra3 + Va3 * Ra2 + Va4 * Ra1 + Va0 * Ra5 + Va5 * Ra0)
    Wa6 = Va5 * 0.14285714285714285
    Va6 = (kca * Wa5 + l2 * Wb5 - Ra6 * amp) * 0.14285714285714285
    Rb6 = k0b * (Vb1 * Rb4 + Vb2 * Rb3 + Vb3 * Rb2 + Vb4 * Rb1 + Vb0 * Rb5 + Vb5 * Rb0)
    Wb6 = Vb5 * 0.14285714285714285
    Vb6 = (kcb * Wb5 + l2 * (Wa5 + Wc5) - Rb6 * amp) * 0.14285714285714285
    Rc6 = k0c * (Vc1 * Rc4 + Vc2 * Rc3 + Vc3 * Rc2 + Vc4 * Rc1 + Vc0 * Rc5 + Vc5 * Rc0)
    Wc6 = Vc5 * 0.14285714285714285
    Vc6 = (kcc * Wc5 + l2 * Wb5 - Rc6 * amp) * 0.14285714285714285
    Ra7 = k0a * (Va1 * Ra5 + Va2 * Ra4 + Va3 * Ra3 + Va4 * Ra2 + Va5 * Ra1 + Va0 * Ra6 + Va6 * Ra0)
    Wa7 = Va6 * 0.125
    Va7 = (kca * Wa6 + l2 * Wb6 - Ra7 * amp) * 0.125
    Rb7 = k0b * (Vb1 * Rb5 + Vb2 * Rb4 + Vb3 * Rb3 + Vb4 * Rb2 + Vb5 * Rb1 + Vb0 * Rb6 + Vb6 * Rb0)
    Wb7 = Vb6 * 0.125
    Vb7 = (kcb * Wb6 + l2 * (Wa6 + Wc6) - Rb7 * amp) * 0.125
    Rc7 = k0c * (Vc1 * Rc5 + Vc2 * Rc4 + Vc3 * Rc3 + Vc4 * Rc2 + Vc5 * Rc1 + Vc0 * Rc6 + Vc6 * Rc0)
    Wc7 = Vc6 * 0.125
    Vc7 = (kcc * Wc6 + l2 * Wb6 - Rc7 * amp) * 0.125
    Ra8 = k0a * (Va1 * Ra6 + Va2 * Ra5 + Va3 * Ra4 + Va4 * Ra3 + Va5 * Ra2 + Va6 * Ra1 + Va0 * Ra7 + Va7 * Ra0)
    Wa8 = Va7 * 0.1111111111111111
    Va8 = (kca * Wa7 + l2 * Wb7 - Ra8 * amp) * 0.1111111111111111
    Rb8 = k0b * (Vb1 * Rb6 + Vb2 * Rb5 + Vb3 * Rb4 + Vb4 * Rb3 + Vb5 * Rb2 + Vb6 * Rb1 + Vb0 * Rb7 + Vb7 * Rb0)
    Wb8 = Vb7 * 0.1111111111111111
    Vb8 = (kcb * Wb7 + l2 * (Wa7 + Wc7) - Rb8 * amp) * 0.1111111111111111
    Rc8 = k0c * (Vc1 * Rc6 + Vc2 * Rc5 + Vc3 * Rc4 + Vc4 * Rc3 + Vc5 * Rc2 + Vc6 * Rc1 + Vc0 * Rc7 + Vc7 * Rc0)
    Wc8 = Vc7 * 0.1111111111111111
    Vc8 = (kcc * Wc7 + l2 * Wb7 - Rc8 * amp) * 0.1111111111111111
    Ra9 = k0a * (Va1 * Ra7 + Va2 * Ra6 + Va3 * Ra5 + Va4 * Ra4 + Va5 * Ra3 + Va6 * Ra2 + Va7 * Ra1 + Va0 * Ra8 + Va8 * Ra0)
    Wa9 = Va8 * 0.1
    Va9 = (kca * Wa8 + l2 * Wb8 - Ra9 * amp) * 0.1
    Rb9 = k0b * (Vb1 * Rb7 + Vb2 * Rb6 + Vb3 * Rb5 + Vb4 * Rb4 + Vb5 * Rb3 + Vb6 * Rb2 + Vb7 * Rb1 + Vb0 * Rb8 + Vb8 * Rb0)
    Wb9 = Vb8 * 0.1
    Vb9 = (kcb * Wb8 + l2 * (Wa8 + Wc8) - Rb9 * amp) * 0.1
    Rc9 = k0c * (Vc1 * Rc7 + Vc2 * Rc6 + Vc3 * Rc5 + Vc4 * Rc4 + Vc5 * Rc3 + Vc6 * Rc2 + Vc7 * Rc1 + Vc0 * Rc8 + Vc8 * Rc0)
    Wc9 = Vc8 * 0.1
    Vc9 = (kcc * Wc8 + l2 * Wb8 - Rc9 * amp) * 0.1
    Ra10 = k0a * (Va1 * Ra8 + Va2 * Ra7 + Va3 * Ra6 + Va4 * Ra5 + Va5 * Ra4 + Va6 * Ra3 + Va7 * Ra2 + Va8 * Ra1 + Va0 * Ra9 + Va9 * Ra0)
    Wa10 = Va9 * 0.09090909090909091
    Va10 = (kca * Wa9 + l2 * Wb9 - Ra10 * amp) * 0.09090909090909091
    Rb10 = k0b * (Vb1 * Rb8 + Vb2 * Rb7 + Vb3 * Rb6 + Vb4 * Rb5 + Vb5 * Rb4 + Vb6 * Rb3 + Vb7 * Rb2 + Vb8 * Rb1 + Vb0 * Rb9 + Vb9 * Rb0)
    Wb10 = Vb9 * 0.09090909090909091
    Vb10 = (kcb * Wb9 + l2 * (Wa9 + Wc9) - Rb10 * amp) * 0.09090909090909091
    Rc10 = k0c * (Vc1 * Rc8 + Vc2 * Rc7 + Vc3 * Rc6 + Vc4 * Rc5 + Vc5 * Rc4 + Vc6 * Rc3 + Vc7 * Rc2 + Vc8 * Rc1 + Vc0 * Rc9 + Vc9 * Rc0)
    Wc10 = Vc9 * 0.09090909090909091
    Vc10 = (kcc * Wc9 + l2 * Wb9 - Rc10 * amp) * 0.09090909090909091
    Ra11 = k0a * (Va1 * Ra9 + Va2 * Ra8 + Va3 * Ra7 + Va4 * Ra6 + Va5 * Ra5 + Va6 * Ra4 + Va7 * Ra3 + Va8 * Ra2 + Va9 * Ra1 + Va0 * Ra10 + Va10 * Ra0)
    Wa11 = Va10 * 0.08333333333333333
    Va11 = (kca * Wa10 + l2 * Wb10 - Ra11 * amp) * 0.08333333333333333
    Rb11 = k0b * (Vb1 * Rb9 + Vb2 * Rb8 + Vb3 * Rb7 + Vb4 * Rb6 + Vb5 * Rb5 + Vb6 * Rb4 + Vb7 * Rb3 + Vb8 * Rb2 + Vb9 * Rb1 + Vb0 * Rb10 + Vb10 * Rb0)
    Wb11 = Vb10 * 0.08333333333333333
    Vb11 = (kcb * Wb10 + l2 * (Wa10 + Wc10) - Rb11 * amp) * 0.08333333333333333
    Rc11 = k0c * (Vc1 * Rc9 + Vc2 * Rc8 + Vc3 * Rc7 + Vc4 * Rc6 + Vc5 * Rc5 + Vc6 * Rc4 + Vc7 * Rc3 + Vc8 * Rc2 + Vc9 * Rc1 + Vc0 * Rc10 + Vc10 * Rc0)
    Wc11 = Vc10 * 0.08333333333333333
    Vc11 = (kcc * Wc10 + l2 * Wb10 - Rc11 * amp) * 0.08333333333333333
    Ra12 = k0a * (Va1 * Ra10 + Va2 * Ra9 + Va3 * Ra8 + Va4 * Ra7 + Va5 * Ra6 + Va6 * Ra5 + Va7 * Ra4 + Va8 * Ra3 + Va9 * Ra2 + Va10 * Ra1 + Va0 * Ra11 + Va11 * Ra0)
    Wa12 = Va11 * 0.07692307692307693
    Va12 = (kca * Wa11 + l2 * Wb11 - Ra12 * amp) * 0.07692307692307693
    Rb12 = k0b * (Vb1 * Rb10 + Vb2 * Rb9 + Vb3 * Rb8 + Vb4 * Rb7 + Vb5 * Rb6 + Vb6 * Rb5 + Vb7 * Rb4 + Vb8 * Rb3 + Vb9 * Rb2 + Vb10 * Rb1 + Vb0 * Rb11 + Vb11 * Rb0)
    Wb12 = Vb11 * 0.07692307692307693
    Vb12 = (kcb * Wb11 + l2 * (Wa11 + Wc11) - Rb12 * amp) * 0.07692307692307693
    Rc12 = k0c * (Vc1 * Rc10 + Vc2 * Rc9 + Vc3 * Rc8 + Vc4 * Rc7 + Vc5 * Rc6 + Vc6 * Rc5 + Vc7 * Rc4 + Vc8 * Rc3 + Vc9 * Rc2 + Vc10 * Rc1 + Vc0 * Rc11 + Vc11 * Rc0)
    Wc12 = Vc11 * 0.07692307692307693
    Vc12 = (kcc * Wc11 + l2 * Wb11 - Rc12 * amp) * 0.07692307692307693
    Ra13 = k0a * (Va1 * Ra11 + Va2 * Ra10 + Va3 * Ra9 + Va4 * Ra8 + Va5 * Ra7 + Va6 * Ra6 + Va7 * Ra5 + Va8 * Ra4 + Va9 * Ra3 + Va10 * Ra2 + Va11 * Ra1 + Va0 * Ra12 + Va12 * Ra0)
    Wa13 = Va12 * 0.07142857142857142
    Va13 = (kca * Wa12 + l2 * Wb12 - Ra13 * amp) * 0.07142857142857142
    Rb13 = k0b * (Vb1 * Rb11 + Vb2 * Rb10 + Vb3 * Rb9 + Vb4 * Rb8 + Vb5 * Rb7 + Vb6 * Rb6 + Vb7 * Rb5 + Vb8 * Rb4 + Vb9 * Rb3 + Vb10 * Rb2 + Vb11 * Rb1 + Vb0 * Rb12 + Vb12 * Rb0)
    Wb13 = Vb12 * 0.07142857142857142
    Vb13 = (kcb * Wb12 + l2 * (Wa12 + Wc12) - Rb13 * amp) * 0.07142857142857142
    Rc13 = k0c * (Vc1 * Rc11 + Vc2 * Rc10 + Vc3 * Rc9 + Vc4 * Rc8 + Vc5 * Rc7 + Vc6 * Rc6 + Vc7 * Rc5 + Vc8 * Rc4 + Vc9 * Rc3 + Vc10 * Rc2 + Vc11 * Rc1 + Vc0 * Rc12 + Vc12 * Rc0)
    Wc13 = Vc12 * 0.07142857142857142
    Vc13 = (kcc * Wc12 + l2 * Wb12 - Rc13 * amp) * 0.07142857142857142
    Ra14 = k0a * (Va1 * Ra12 + Va2 * Ra11 + Va3 * Ra10 + Va4 * Ra9 + Va5 * Ra8 + Va6 * Ra7 + Va7 * Ra6 + Va8 * Ra5 + Va9 * Ra4 + Va10 * Ra3 + Va11 * Ra2 + Va12 * Ra1 + Va0 * Ra13 + Va13 * Ra0)
    Wa14 = Va13 * 0.06666666666666667
    Va14 = (kca * Wa13 + l2 * Wb13 - Ra14 * amp) * 0.06666666666666667
    Rb14 = k0b * (Vb1 * Rb12 + Vb2 * Rb11 + Vb3 * Rb10 + Vb4 * Rb9 + Vb5 * Rb8 + Vb6 * Rb7 + Vb7 * Rb6 + Vb8 * Rb5 + Vb9 * Rb4 + Vb10 * Rb3 + Vb11 * Rb2 + Vb12 * Rb1 + Vb0 * Rb13 + Vb13 * Rb0)
    Wb14 = Vb13 * 0.06666666666666667
    Vb14 = (kcb * Wb13 + l2 * (Wa13 + Wc13) - Rb14 * amp) * 0.06666666666666667
    Rc14 = k0c * (Vc1 * Rc12 + Vc2 * Rc11 + Vc3 * Rc10 + Vc4 * Rc9 + Vc5 * Rc8 + Vc6 * Rc7 + Vc7 * Rc6 + Vc8 * Rc5 + Vc9 * Rc4 + Vc10 * Rc3 + Vc11 * Rc2 + Vc12 * Rc1 + Vc0 * Rc13 + Vc13 * Rc0)
    Wc14 = Vc13 * 0.06666666666666667
    Vc14 = (kcc * Wc13 + l2 * Wb13 - Rc14 * amp) * 0.06666666666666667
    Ra15 = k0a * (Va1 * Ra13 + Va2 * Ra12 + Va3 * Ra11 + Va4 * Ra10 + Va5 * Ra9 + Va6 * Ra8 + Va7 * Ra7 + Va8 * Ra6 + Va9 * Ra5 + Va10 * Ra4 + Va11 * Ra3 + Va12 * Ra2 + Va13 * Ra1 + Va0 * Ra14 + Va14 * Ra0)
    Wa15 = Va14 * 0.0625
    Va15 = (kca * Wa14 + l2 * Wb14 - Ra15 * amp) * 0.0625
    Rb15 = k0b * (Vb1 * Rb13 + Vb2 * Rb12 + Vb3 * Rb11 + Vb4 * Rb10 + Vb5 * Rb9 + Vb6 * Rb8 + Vb7 * Rb7 + Vb8 * Rb6 + Vb9 * Rb5 + Vb10 * Rb4 + Vb11 * Rb3 + Vb12 * Rb2 + Vb13 * Rb1 + Vb0 * Rb14 + Vb14 * Rb0)
    Wb15 = Vb14 * 0.0625
    Vb15 = (kcb * Wb14 + l2 * (Wa14 + Wc14) - Rb15 * amp) * 0.0625
    Rc15 = k0c * (Vc1 * Rc13 + Vc2 * Rc12 + Vc3 * Rc11 + Vc4 * Rc10 + Vc5 * Rc9 + Vc6 * Rc8 + Vc7 * Rc7 + Vc8 * Rc6 + Vc9 * Rc5 + Vc10 * Rc4 + Vc11 * Rc3 + Vc12 * Rc2 + Vc13 * Rc1 + Vc0 * Rc14 + Vc14 * Rc0)
    Wc15 = Vc14 * 0.0625
    Vc15 = (kcc * Wc14 + l2 * Wb14 - Rc15 * amp) * 0.0625
    Ra16 = k0a * (Va1 * Ra14 + Va2 * Ra13 + Va3 * Ra12 + Va4 * Ra11 + Va5 * Ra10 + Va6 * Ra9 + Va7 * Ra8 + Va8 * Ra7 + Va9 * Ra6 + Va10 * Ra5 + Va11 * Ra4 + Va12 * Ra3 + Va13 * Ra2 + Va14 * Ra1 + Va0 * Ra15 + Va15 * Ra0)
    Wa16 = Va15 * 0.058823529411764705
    Va16 = (kca * Wa15 + l2 * Wb15 - Ra16 * amp) * 0.058823529411764705
    Rb16 = k0b * (Vb1 * Rb14 + Vb2 * Rb13 + Vb3 * Rb12 + Vb4 * Rb11 + Vb5 * Rb10 + Vb6 * Rb9 + Vb7 * Rb8 + Vb8 * Rb7 + Vb9 * Rb6 + Vb10 * Rb5 + Vb11 * Rb4 + Vb12 * Rb3 + Vb13 * Rb2 + Vb14 * Rb1 + Vb0 * Rb15 + Vb15 * Rb0)
    Wb16 = Vb15 * 0.058823529411764705
    Vb16 = (kcb * Wb15 + l2 * (Wa15 + Wc15) - Rb16 * amp) * 0.058823529411764705
    Rc16 = k0c * (Vc1 * Rc14 + Vc2 * Rc13 + Vc3 * Rc12 + Vc4 * Rc11 + Vc5 * Rc10 + Vc6 * Rc9 + Vc7 * Rc8 + Vc8 * Rc7 + Vc9 * Rc6 + Vc10 * Rc5 + Vc11 * Rc4 + Vc12 * Rc3 + Vc13 * Rc2 + Vc14 * Rc1 + Vc0 * Rc15 + Vc15 * Rc0)
    Wc16 = Vc15 * 0.058823529411764705
    Vc16 = (kcc * Wc15 + l2 * Wb15 - Rc16 * amp) * 0.058823529411764705
    Ra17 = k0a * (Va1 * Ra15 + Va2 * Ra14 + Va3 * Ra13 + Va4 * Ra12 + Va5 * Ra11 + Va6 * Ra10 + Va7 * Ra9 + Va8 * Ra8 + Va9 * Ra7 + Va10 * Ra6 + Va11 * Ra5 + Va12 * Ra4 + Va13 * Ra3 + Va14 * Ra2 + Va15 * Ra1 + Va0 * Ra16 + Va16 * Ra0)
    Wa17 = Va16 * 0.05555555555555555
    Va17 = (kca * Wa16 + l2 * Wb16 - Ra17 * amp) * 0.05555555555555555
    Rb17 = k0b * (Vb1 * Rb15 + Vb2 * Rb14 + Vb3 * Rb13 + Vb4 * Rb12 + Vb5 * Rb11 + Vb6 * Rb10 + Vb7 * Rb9 + Vb8 * Rb8 + Vb9 * Rb7 + Vb10 * Rb6 + Vb11 * Rb5 + Vb12 * Rb4 + Vb13 * Rb3 + Vb14 * Rb2 + Vb15 * Rb1 + Vb0 * Rb16 + Vb16 * Rb0)
    Wb17 = Vb16 * 0.05555555555555555
    Vb17 = (kcb * Wb16 + l2 * (Wa16 + Wc16) - Rb17 * amp) * 0.05555555555555555
    Rc17 = k0c * (Vc1 * Rc15 + Vc2 * Rc14 + Vc3 * Rc13 + Vc4 * Rc12 + Vc5 * Rc11 + Vc6 * Rc10 + Vc7 * Rc9 + Vc8 * Rc8 + Vc9 * Rc7 + Vc10 * Rc6 + Vc11 * Rc5 + Vc12 * Rc4 + Vc13 * Rc3 + Vc14 * Rc2 + Vc15 * Rc1 + Vc0 * Rc16 + Vc16 * Rc0)
    Wc17 = Vc16 * 0.05555555555555555
    Vc17 = (kcc * Wc16 + l2 * Wb16 - Rc17 * amp) * 0.05555555555555555
    Ra18 = k0a * (Va1 * Ra16 + Va2 * Ra15 + Va3 * Ra14 + Va4 * Ra13 + Va5 * Ra12 + Va6 * Ra11 + Va7 * Ra10 + Va8 * Ra9 + Va9 * Ra8 + Va10 * Ra7 + Va11 * Ra6 + Va12 * Ra5 + Va13 * Ra4 + Va14 * Ra3 + Va15 * Ra2 + Va16 * Ra1 + Va0 * Ra17 + Va17 * Ra0)
    Wa18 = Va17 * 0.05263157894736842
    Va18 = (kca * Wa17 + l2 * Wb17 - Ra18 * amp) * 0.05263157894736842
    Rb18 = k0b * (Vb1 * Rb16 + Vb2 * Rb15 + Vb3 * Rb14 + Vb4 * Rb13 + Vb5 * Rb12 + Vb6 * Rb11 + Vb7 * Rb10 + Vb8 * Rb9 + Vb9 * Rb8 + Vb10 * Rb7 + Vb11 * Rb6 + Vb12 * Rb5 + Vb13 * Rb4 + Vb14 * Rb3 + Vb15 * Rb2 + Vb16 * Rb1 + Vb0 * Rb17 + Vb17 * Rb0)
    Wb18 = Vb17 * 0.05263157894736842
    Vb18 = (kcb * Wb17 + l2 * (Wa17 + Wc17) - Rb18 * amp) * 0.05263157894736842
    Rc18 = k0c * (Vc1 * Rc16 + Vc2 * Rc15 + Vc3 * Rc14 + Vc4 * Rc13 + Vc5 * Rc12 + Vc6 * Rc11 + Vc7 * Rc10 + Vc8 * Rc9 + Vc9 * Rc8 + Vc10 * Rc7 + Vc11 * Rc6 + Vc12 * Rc5 + Vc13 * Rc4 + Vc14 * Rc3 + Vc15 * Rc2 + Vc16 * Rc1 + Vc0 * Rc17 + Vc17 * Rc0)
    Wc18 = Vc17 * 0.05263157894736842
    Vc18 = (kcc * Wc17 + l2 * Wb17 - Rc18 * amp) * 0.05263157894736842
    Ra19 = k0a * (Va1 * Ra17 + Va2 * Ra16 + Va3 * Ra15 + Va4 * Ra14 + Va5 * Ra13 + Va6 * Ra12 + Va7 * Ra11 + Va8 * Ra10 + Va9 * Ra9 + Va10 * Ra8 + Va11 * Ra7 + Va12 * Ra6 + Va13 * Ra5 + Va14 * Ra4 + Va15 * Ra3 + Va16 * Ra2 + Va17 * Ra1 + Va0 * Ra18 + Va18 * Ra0)
    Wa19 = Va18 * 0.05
    Va19 = (kca * Wa18 + l2 * Wb18 - Ra19 * amp) * 0.05
    Rb19 = k0b * (Vb1 * Rb17 + Vb2 * Rb16 + Vb3 * Rb15 + Vb4 * Rb14 + Vb5 * Rb13 + Vb6 * Rb12 + Vb7 * Rb11 + Vb8 * Rb10 + Vb9 * Rb9 + Vb10 * Rb8 + Vb11 * Rb7 + Vb12 * Rb6 + Vb13 * Rb5 + Vb14 * Rb4 + Vb15 * Rb3 + Vb16 * Rb2 + Vb17 * Rb1 + Vb0 * Rb18 + Vb18 * Rb0)
    Wb19 = Vb18 * 0.05
    Vb19 = (kcb * Wb18 + l2 * (Wa18 + Wc18) - Rb19 * amp) * 0.05
    Rc19 = k0c * (Vc1 * Rc17 + Vc2 * Rc16 + Vc3 * Rc15 + Vc4 * Rc14 + Vc5 * Rc13 + Vc6 * Rc12 + Vc7 * Rc11 + Vc8 * Rc10 + Vc9 * Rc9 + Vc10 * Rc8 + Vc11 * Rc7 + Vc12 * Rc6 + Vc13 * Rc5 + Vc14 * Rc4 + Vc15 * Rc3 + Vc16 * Rc2 + Vc17 * Rc1 + Vc0 * Rc18 + Vc18 * Rc0)
    Wc19 = Vc18 * 0.05
    Vc19 = (kcc * Wc18 + l2 * Wb18 - Rc19 * amp) * 0.05
    fw[i, 1], fv[i, 1], cr[i, 1] = Wa1, Va1, Ra1
    fw[j, 1], fv[j, 1], cr[j, 1] = Wb1, Vb1, Rb1
    fw[k, 1], fv[k, 1], cr[k, 1] = Wc1, Vc1, Rc1
    fw[i, 2], fv[i, 2], cr[i, 2] = Wa2, Va2, Ra2
    fw[j, 2], fv[j, 2], cr[j, 2] = Wb2, Vb2, Rb2
    fw[k, 2], fv[k, 2], cr[k, 2] = Wc2, Vc2, Rc2
    fw[i, 3], fv[i, 3], cr[i, 3] = Wa3, Va3, Ra3
    fw[j, 3], fv[j, 3], cr[j, 3] = Wb3, Vb3, Rb3
    fw[k, 3], fv[k, 3], cr[k, 3] = Wc3, Vc3, Rc3
    fw[i, 4], fv[i, 4], cr[i, 4] = Wa4, Va4, Ra4
    fw[j, 4], fv[j, 4], cr[j, 4] = Wb4, Vb4, Rb4
    fw[k, 4], fv[k, 4], cr[k, 4] = Wc4, Vc4, Rc4
    fw[i, 5], fv[i, 5], cr[i, 5] = Wa5, Va5, Ra5
    fw[j, 5], fv[j, 5], cr[j, 5] = Wb5, Vb5, Rb5
    fw[k, 5], fv[k, 5], cr[k, 5] = Wc5, Vc5, Rc5
    fw[i, 6], fv[i, 6], cr[i, 6] = Wa6, Va6, Ra6
    fw[j, 6], fv[j, 6], cr[j, 6] = Wb6, Vb6, Rb6
    fw[k, 6], fv[k, 6], cr[k, 6] = Wc6, Vc6, Rc6
    fw[i, 7], fv[i, 7], cr[i, 7] = Wa7, Va7, Ra7
    fw[j, 7], fv[j, 7], cr[j, 7] = Wb7, Vb7, Rb7
    fw[k, 7], fv[k, 7], cr[k, 7] = Wc7, Vc7, Rc7
    fw[i, 8], fv[i, 8], cr[i, 8] = Wa8, Va8, Ra8
    fw[j, 8], fv[j, 8], cr[j, 8] = Wb8, Vb8, Rb8
    fw[k, 8], fv[k, 8], cr[k, 8] = Wc8, Vc8, Rc8
    fw[i, 9], fv[i, 9], cr[i, 9] = Wa9, Va9, Ra9
    fw[j, 9], fv[j, 9], cr[j, 9] = Wb9, Vb9, Rb9
    fw[k, 9], fv[k, 9], cr[k, 9] = Wc9, Vc9, Rc9
    fw[i, 10], fv[i, 10], cr[i, 10] = Wa10, Va10, Ra10
    fw[j, 10], fv[j, 10], cr[j, 10] = Wb10, Vb10, Rb10
    fw[k, 10], fv[k, 10], cr[k, 10] = Wc10, Vc10, Rc10
    fw[i, 11], fv[i, 11], cr[i, 11] = Wa11, Va11, Ra11
    fw[j, 11], fv[j, 11], cr[j, 11] = Wb11, Vb11, Rb11
    fw[k, 11], fv[k, 11], cr[k, 11] = Wc11, Vc11, Rc11
    fw[i, 12], fv[i, 12], cr[i, 12] = Wa12, Va12, Ra12
    fw[j, 12], fv[j, 12], cr[j, 12] = Wb12, Vb12, Rb12
    fw[k, 12], fv[k, 12], cr[k, 12] = Wc12, Vc12, Rc12
    fw[i, 13], fv[i, 13], cr[i, 13] = Wa13, Va13, Ra13
    fw[j, 13], fv[j, 13], cr[j, 13] = Wb13, Vb13, Rb13
    fw[k, 13], fv[k, 13], cr[k, 13] = Wc13, Vc13, Rc13
    fw[i, 14], fv[i, 14], cr[i, 14] = Wa14, Va14, Ra14
    fw[j, 14], fv[j, 14], cr[j, 14] = Wb14, Vb14, Rb14
    fw[k, 14], fv[k, 14], cr[k, 14] = Wc14, Vc14, Rc14
    fw[i, 15], fv[i, 15], cr[i, 15] = Wa15, Va15, Ra15
    fw[j, 15], fv[j, 15], cr[j, 15] = Wb15, Vb15, Rb15
    fw[k, 15], fv[k, 15], cr[k, 15] = Wc15, Vc15, Rc15
    fw[i, 16], fv[i, 16], cr[i, 16] = Wa16, Va16, Ra16
    fw[j, 16], fv[j, 16], cr[j, 16] = Wb16, Vb16, Rb16
    fw[k, 16], fv[k, 16], cr[k, 16] = Wc16, Vc16, Rc16
    fw[i, 17], fv[i, 17], cr[i, 17] = Wa17, Va17, Ra17
    fw[j, 17], fv[j, 17], cr[j, 17] = Wb17, Vb17, Rb17
    fw[k, 17], fv[k, 17], cr[k, 17] = Wc17, Vc17, Rc17
    fw[i, 18], fv[i, 18], cr[i, 18] = Wa18, Va18, Ra18
    fw[j, 18], fv[j, 18], cr[j, 18] = Wb18, Vb18, Rb18
    fw[k, 18], fv[k, 18], cr[k, 18] = Wc18, Vc18, Rc18
    fw[i, 19], fv[i, 19], cr[i, 19] = Wa19, Va19, Ra19
    fw[j, 19], fv[j, 19], cr[j, 19] = Wb19, Vb19, Rb19
    fw[k, 19], fv[k, 19], cr[k, 19] = Wc19, Vc19, Rc19
# -- end of generated code


@_inline
def _taylor(m, tau, win, fr, l2, rtol, atol):
    """Taylor coefficients about τ of the window's slipping slots (Carlson–Langer: g_σ = σ_f + (1 − σ_f) x/(1 + x),
    x = fr[3] v, whose series follows from that of 1/(1 + x) by the usual recurrence; stuck slots have
    constant w, zero rows), stored unscaled in win.fw/fv (F[i, k − 1] = c_k). Returns the largest step h
    with |c_q| h^q ≤ 0.9^q (atol + rtol max(|w_i|, |v_i|)) for q = p − 1, p and every slipping slot i, as
    heyoka's step rule on the last two terms (per block, not over the window: a slow block's stop, a root
    of v with a small slope, was 1.1e-10 off in duration on the window's norm), or NaN if a coefficient is
    not finite."""
    slip, left, right, selfc, d = win.slip, win.left, win.right, win.selfc, win.dn
    w, v, fw, fv, cr = win.w, win.v, win.fw, win.fv, win.cr
    P = fw.shape[1]
    c3, sig, c4 = fr[3], fr[2], fr[4]
    amp = (1.0 - sig) * c4
    idx = win.nblk          # (``_rebuild``'s scratch, free here): the slipping slots, so the order loop skips no slot
    # (a stuck slot's rows are zero: ``_segment`` zeroes them when the segment starts and when a block stops)
    ns = 0
    for i in range(m):
        if slip[i]:
            idx[ns] = i
            ns += 1
            cr[i, 0] = 1.0 / (1.0 + c3 * v[i])
            lf, rt = left[i], right[i]
            wn, vn = w[i], v[i]
            c = (selfc[i] - 2.0) * wn
            if lf >= 0:
                c += w[lf]
            if rt >= 0:
                c += w[rt]
            xs = c3 * vn
            g = xs / (1.0 + xs)
            gt = g * c4 if sig == 0.0 else (sig + (1.0 - sig) * g) * c4
            fw[i, 0] = vn
            fv[i, 0] = (d[i] + l2 * c - wn + tau) + gt
    # runs of one, two or three slipping slots whose other neighbours are stuck (a stuck slot's rows are zero:
    # nothing couples through it past order 0) by kernels written out in scalars, their sums ordered to shorten
    # the dependency from one order to the next (``_taylor_block``, ``_taylor_pair``, ``_taylor_triple``);
    # longer runs and rings by the loop
    coupled = P != 20
    for t in range(ns):
        i = idx[t]
        lf, rt = left[i], right[i]
        sl = lf >= 0 and slip[lf] != 0
        sr = rt >= 0 and slip[rt] != 0
        if (sl or sr) and lf == rt:
            coupled = True                   # two blocks on a ring: each the other's both neighbours
        if sl and sr:                        # the middle of a run: its ends' other neighbours must be stuck
            a, b = left[lf], right[rt]
            if (a >= 0 and slip[a] != 0) or (b >= 0 and slip[b] != 0):
                coupled = True
    if not coupled:
        for t in range(ns):
            i = idx[t]
            lf, rt = left[i], right[i]
            if lf >= 0 and slip[lf]:
                continue                     # not the run's left end: done with it
            if rt >= 0 and slip[rt]:
                r2 = right[rt]
                if r2 >= 0 and slip[r2]:
                    _taylor_triple(fw, fv, cr, i, rt, r2, selfc[i] - 2.0, selfc[rt] - 2.0, selfc[r2] - 2.0,
                                   c3, amp, l2)
                else:
                    _taylor_pair(fw, fv, cr, i, rt, selfc[i] - 2.0, selfc[rt] - 2.0, c3, amp, l2)
            else:
                _taylor_block(fw, fv, cr, i, selfc[i] - 2.0, c3, amp, l2)
    nl = ns if coupled else 0
    for n in range(1, P):
        for t in range(nl):
            i = idx[t]
            lf, rt = left[i], right[i]
            wn, vn = fw[i, n - 1], fv[i, n - 1]
            c = (selfc[i] - 2.0) * wn
            if lf >= 0:
                c += fw[lf, n - 1]
            if rt >= 0:
                c += fw[rt, n - 1]
            # Σ_{j=1..n} v_j r_{n−j} in one accumulator: four partial sums were measured 15 % slower, and
            # shortening the order-to-order dependency chain (r_(n+1) = A + B r_n) did not speed the step
            # either (docs/chain.md, "Engines"), so that chain is not what bounds it
            acc_ = 0.0
            for j in range(1, n + 1):
                acc_ += fv[i, j - 1] * cr[i, n - j]
            rn = -(c3 * acc_) * cr[i, 0]
            cr[i, n] = rn
            gt = -rn * amp
            ld = l2 * c - wn
            if n == 1:
                ld += 1.0
            fw[i, n] = vn / (n + 1)
            fv[i, n] = (ld + gt) / (n + 1)
    a_1, a_0 = 0.0, 0.0      # the largest scaled last and next-to-last coefficients (one pow each)
    for t in range(ns):
        i = idx[t]
        ev = atol + rtol * abs(v[i])
        ew = max(ev, atol + rtol * abs(w[i]))
        a_1 = max(a_1, abs(fw[i, P - 2]) / ew, abs(fv[i, P - 2]) / ev)
        a_0 = max(a_0, abs(fw[i, P - 1]) / ew, abs(fv[i, P - 1]) / ev)
    if not (a_1 < np.inf and a_0 < np.inf):
        return np.nan
    h = np.inf
    if a_1 > 0.0:
        h = (1.0 / a_1) ** (1.0 / (P - 1))
    if a_0 > 0.0:
        h = min(h, (1.0 / a_0) ** (1.0 / P))
    return 0.9 * h


@_inline
def _taylor_step(m, h, win, kv):
    """Scale the coefficients to θ = τ/h (F[i, k − 1] = c_k h^k), the state at the step's end (win.w1/v1),
    the accelerations at its ends (kv[i, 0], kv[i, 12]) as DOP853's first and last stages. Returns
    (err, Σ|err(w)|, Σ|err(v)|) with the last terms as the local error estimates."""
    slip, w, v, fw, fv, w1, v1 = win.slip, win.w, win.v, win.fw, win.fv, win.w1, win.v1
    P = fw.shape[1]
    ew = 0.0
    ev = 0.0
    for i in range(m):
        if not slip[i]:
            w1[i] = w[i]
            v1[i] = v[i]
            kv[i, 0] = 0.0
            kv[i, 12] = 0.0
            continue
        kv[i, 0] = fv[i, 0]
        hk = 1.0
        dv = 0.0
        for q in range(P):
            dv += (q + 1) * fv[i, q] * hk     # v'(h) = Σ k c_k h^(k−1)
            hk *= h
            fw[i, q] *= hk
            fv[i, q] *= hk
        kv[i, 12] = dv
        ew += abs(fw[i, P - 1])
        ev += abs(fv[i, P - 1])
        sw = 0.0
        sv = 0.0
        for q in range(P - 1, -1, -1):
            sw += fw[i, q]
            sv += fv[i, q]
        w1[i] = w[i] + sw
        v1[i] = v[i] + sv
    return 0.5, ew, ev


@_jit
def _dense_prepare(m, h, tau, win, law, gfun, fr, l2):
    """The three extra stages and the 7 dense-output rows of the last step (w and v); nothing for a Taylor
    step (its polynomial is the dense output)."""
    if win.fw.shape[1] != 7:
        return
    slip, piece, left, right, selfc, d = win.slip, win.piece, win.left, win.right, win.selfc, win.dn
    code, consts, tstart, regs = law.code, law.consts, law.start, law.regs   # (a named tuple's field: ~400 ns per read)
    kw, kv, tw, tv, w, v, w1, v1 = win.kw, win.kv, win.tw, win.tv, win.w, win.v, win.w1, win.v1
    for s in range(13, 16):
        for i in range(m):
            aw = 0.0
            av = 0.0
            for r in range(s):
                a = _A[s, r]
                if a != 0.0:
                    aw += a * kw[i, r]
                    av += a * kv[i, r]
            tw[i] = w[i] + h * aw
            tv[i] = v[i] + h * av
        _rhs(m, tw, tv, tau + _CC[s] * h, slip, piece, left, right, selfc, d, gfun, code, consts, tstart, regs, fr, l2, kw, kv, s)
    Fw, Fv = win.fw, win.fv
    for i in range(m):
        dw = w1[i] - w[i]
        dv = v1[i] - v[i]
        Fw[i, 0] = dw
        Fv[i, 0] = dv
        Fw[i, 1] = h * kw[i, 0] - dw
        Fv[i, 1] = h * kv[i, 0] - dv
        Fw[i, 2] = 2.0 * dw - h * (kw[i, 12] + kw[i, 0])
        Fv[i, 2] = 2.0 * dv - h * (kv[i, 12] + kv[i, 0])
        for q in range(4):
            sw = 0.0
            sv = 0.0
            for r in range(16):
                dq = _D[q, r]
                if dq != 0.0:
                    sw += dq * kw[i, r]
                    sv += dq * kv[i, r]
            Fw[i, 3 + q] = h * sw
            Fv[i, 3 + q] = h * sv


@_inline
def _event_value(kind, i, th, win, tau, h, l2, nu, target):
    """The event function of slot i at θ on the dense output: kind 0 stop (v), 1 start ((σ − 1)/ν),
    2 switch (v − v_break)."""
    if kind == 1:     # (a stuck slot's dense output is its start value: zero rows, no polynomial to evaluate)
        lf, rt = win.left[i], win.right[i]
        wi = _dense_called(win.fw, win.w, i, th) if win.slip[i] else win.w[i]
        c = (win.selfc[i] - 2.0) * wi
        if lf >= 0:
            c += _dense_called(win.fw, win.w, lf, th) if win.slip[lf] else win.w[lf]
        if rt >= 0:
            c += _dense_called(win.fw, win.w, rt, th) if win.slip[rt] else win.w[rt]
        return win.dn[i] + l2 * c - wi + (tau + th * h)
    return _dense(win.fv, win.v, i, th) - target


@_inline   # (a call copies the window's arrays: 3 % per event at N = 64)
def _root(kind, i, win, tau, h, l2, nu, target, f0, f1):
    """θ in (0, 1] past the sign change of the event function (f0 at 0, f1 at 1), to rounding
    (Illinois regula falsi, bisection as a fallback)."""
    a, b = 0.0, 1.0
    fa, fb = f0, f1
    side = 0
    for it in range(200):
        if b - a <= 2.2e-16 * max(b, 1e-300):
            break
        if it % 4 == 3:
            c = 0.5 * (a + b)
        else:
            c = (a * fb - b * fa) / (fb - fa)
            if not (a < c < b):
                c = 0.5 * (a + b)
        fc = _event_value(kind, i, c, win, tau, h, l2, nu, target)
        if fc == 0.0:
            return c
        if (fc > 0.0) == (fa > 0.0):
            a, fa = c, fc
            if side == -1:
                fb *= 0.5
            side = -1
        else:
            b, fb = c, fc
            if side == 1:
                fa *= 0.5
            side = 1
    return b


@_jit
def _root_called(kind, i, win, tau, h, l2, nu, target, f0, f1):
    """``_root`` called, not inlined: for the rare friction-piece switches and velocity thresholds (three call
    sites, each an inlined copy of the root finder to compile; see ``_dense_called``)."""
    return _root(kind, i, win, tau, h, l2, nu, target, f0, f1)


@_jit
def _bisect(kind, i, win, tau, h, l2, nu, target, a, b, neg):
    """θ in (a, b] past the sign change of the event function (< 0 at a if ``neg``, else > 0; the other
    side at b), to rounding, by bisection (rare paths: ``_start_before``, ``_past_excursion``)."""
    while b - a > 2.2e-16 * b:
        c = 0.5 * (a + b)
        if not (a < c < b):
            break
        if (_event_value(kind, i, c, win, tau, h, l2, nu, target) < 0.0) == neg:
            a = c
        else:
            b = c
    return b


@_jit
def _start_before(i, win, tau, h, l2, nu, lim):
    """θ in (0, lim] where stuck slot i starts ((σ − 1)/ν reaches 0 on the dense output), or 2 if it
    is still below at lim. The step's first stop or switch is at lim: up to there every slipping block
    moves forward, so σ_i rises monotonically and its value at lim decides; past a stop the dense
    output continues the stopped neighbour backwards, so σ_i at the step's end can be back below 1
    (a restart missed: tests/test_chain_compiled.py)."""
    if _event_value(1, i, lim, win, tau, h, l2, nu, 0.0) < 0.0:
        return 2.0
    return _bisect(1, i, win, tau, h, l2, nu, 0.0, 0.0, lim, True)


@_jit
def _extremum(i, win, sg):
    """θ in [0, 1] of the largest sg·v of slot i on the step's dense output (golden section)."""
    g = 0.6180339887498949
    a, b = 0.0, 1.0
    c = b - g * (b - a)
    d = a + g * (b - a)
    fc = sg * _dense_called(win.fv, win.v, i, c)
    fd = sg * _dense_called(win.fv, win.v, i, d)
    for _ in range(80):
        if b - a < 1e-12:
            break
        if fc > fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = sg * _dense_called(win.fv, win.v, i, c)
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = sg * _dense_called(win.fv, win.v, i, d)
    return c if fc > fd else d


@_jit
def _past_excursion(i, win, tau, h, l2, nu, vb, up):
    """θ where slot i crosses the breakpoint velocity vb upwards (``up``) or downwards after an
    excursion, having started the step at vb (switched there): from the excursion's extremum, not
    from θ = 0, where the event function is 0 and a root was found at 3.6e-15 (the block switched
    back and forth there until max_steps). 2 if no excursion is seen."""
    sg = -1.0 if up else 1.0
    th = _extremum(i, win, sg)
    if sg * (_dense_called(win.fv, win.v, i, th) - vb) <= 0.0:
        return 2.0
    return _bisect(2, i, win, tau, h, l2, nu, vb, th, 1.0, up)


@_jit
def _reach(i, kv, h, va, vb, dip, scale, law, pc):
    """Whether v of slot i can reach 0 or its piece's lower bound (``dip``), or its upper bound, inside
    the step: v moves from its ends by at most h × the largest stage acceleration that way, doubled as a
    margin (the stages sample the acceleration at 13 points of the step); skips most extremum searches."""
    reach = 0.0
    for r in range(13):
        a = -kv[i, r] if dip else kv[i, r]
        if a > reach:
            reach = a
    reach *= 2.0 * h
    if dip:
        return min(va, vb) - reach <= (law.lower[pc] * scale if pc > 0 else 0.0)
    return max(va, vb) + reach >= law.upper[pc] * scale


@_jit
def _inside(i, win, tau, h, l2, nu, nu_fs, law, pc, dip):
    """An event inside the step that the ends do not show, at an extremum of v of slipping slot i (a
    minimum if ``dip``): v down to 0 (a stop) or across its piece's lower bound, or up across its upper
    bound, and back. (θ, kind, breakpoint), θ = 2 if none. A step of the three-piece law carried a block
    over x = 1.5 and back at tol 1e-11 (potency 7e-8 off the exact engine, whose root isolation sees
    every root of a step)."""
    sg = -1.0 if dip else 1.0
    th = _extremum(i, win, sg)
    ve = _dense_called(win.fv, win.v, i, th)
    if dip:
        if ve <= 0.0:
            return _bisect(0, i, win, tau, h, l2, nu, 0.0, 0.0, th, False), 0, -1
        if pc > 0 and (nu * ve) / nu_fs < law.lower[pc]:
            vb = law.lower[pc] * nu_fs / nu
            return _bisect(2, i, win, tau, h, l2, nu, vb, 0.0, th, False), 2, pc - 1
    elif (nu * ve) / nu_fs >= law.upper[pc]:
        vb = law.upper[pc] * nu_fs / nu
        return _bisect(2, i, win, tau, h, l2, nu, vb, 0.0, th, True), 2, pc
    return 2.0, -1, -1


@_inline
def _slope(F, i, th):
    """d/dθ of a Taylor step's dense output (``_dense``) of slot i at θ."""
    kk = F.shape[1]
    y = kk * F[i, kk - 1]
    for q in range(kk - 2, -1, -1):
        y = y * th + (q + 1) * F[i, q]
    return y


@_inline
def _vmax_in(i, win, lim):
    """Largest v of slot i on the dense output over θ ∈ [0, lim] (``_vmax_at``'s value)."""
    return _vmax_at(i, win, lim)[0]


@_inline
def _slope2(F, i, th):
    """(d/dθ, d²/dθ²) of a Taylor step's dense output of slot i at θ, in one Horner pass."""
    kk = F.shape[1]
    y = kk * F[i, kk - 1]
    dy = 0.0
    for q in range(kk - 2, -1, -1):
        dy = dy * th + y
        y = y * th + (q + 1) * F[i, q]
    return y, dy


@_jit
def _vmax_at(i, win, lim):
    """(largest v of slot i on the dense output over θ ∈ [0, lim], its θ) by golden section; on a Taylor
    step whose slope falls from > 0 to < 0 over [0, lim], the slope's root by Newton's method (the second
    derivative from the same Horner pass) kept inside the bracket. The maximum's value is flat in θ: a θ
    within 1e-10 of the root moves v by ~|v''| 1e-20, so Newton stops there (3–4 evaluations; the Illinois
    iteration to rounding it replaces took ~15, 4.5 % of the run at N = 64, and golden section ~57)."""
    F = win.fv
    if F.shape[1] != 7:
        a, b = 0.0, lim
        fa, fb = _slope(F, i, a), _slope(F, i, b)
        if fa > 0.0 and fb < 0.0:
            x = a + (b - a) * (fa / (fa - fb))
            if not (a < x < b):
                x = 0.5 * (a + b)
            for _ in range(100):
                s, ds = _slope2(F, i, x)
                if s == 0.0:
                    break
                if s > 0.0:
                    a = x
                else:
                    b = x
                xn = x - s / ds if ds < 0.0 else 0.5 * (a + b)
                if not (a < xn < b):
                    xn = 0.5 * (a + b)
                done = abs(xn - x) <= 1e-10 * lim or b - a <= 1e-10 * lim
                x = xn
                if done:
                    break
            return _dense_called(F, win.v, i, x), x
        if fa > 0.0 and fb >= 0.0:
            # rising up to lim (a cut before the maximum): the largest v is v(lim), where golden section's ~57
            # evaluations converged to within 1e-12 (v a part in ~1e-12 low)
            return _dense_called(F, win.v, i, lim), lim
    g = 0.6180339887498949
    a, b = 0.0, lim
    c = b - g * (b - a)
    d = a + g * (b - a)
    fc = _dense_called(win.fv, win.v, i, c)
    fd = _dense_called(win.fv, win.v, i, d)
    for _ in range(80):
        if b - a < 1e-12:
            break
        if fc > fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = _dense_called(win.fv, win.v, i, c)
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = _dense_called(win.fv, win.v, i, d)
    return (fc, c) if fc > fd else (fd, d)


# -- the largest stress outside the windows: a tournament tree ---------------------------------------
@_jit
def tree_set(tv, ti, p, j, val):
    """Leaf j := val; ancestors keep the index of their largest leaf (the lowest index on ties, as
    numpy's argmax in the heyoka engine)."""
    tv[j] = val
    k = (p + j) >> 1
    while k >= 1:
        a, b = ti[2 * k], ti[2 * k + 1]
        ti[k] = a if tv[a] >= tv[b] else b
        k >>= 1


@_jit
def tree_build(tv, ti, p):
    for j in range(p):
        ti[p + j] = j
    for k in range(p - 1, 0, -1):
        a, b = ti[2 * k], ti[2 * k + 1]
        ti[k] = a if tv[a] >= tv[b] else b


# -- windows -----------------------------------------------------------------------------------------
@_jit
def _neighbours(b, n, periodic):
    """(left, right, free-end self coupling) of block b; −1 for a missing neighbour."""
    if periodic:
        return (b - 1) % n, (b + 1) % n, 0.0
    lf = b - 1 if b > 0 else -1
    rt = b + 1 if b < n - 1 else -1
    return lf, rt, (1.0 if lf < 0 else 0.0) + (1.0 if rt < 0 else 0.0)


@_jit
def _rebuild(m, win, g, starts, ns, base, lam, n, periodic, cnt, nu):
    """The window after a commit: the slipping blocks (those of ``starts`` started now, σ = 1 exactly)
    and their neighbours; blocks that leave go back to the tree. Returns (M, blocks touched first)."""
    slot, mem, pend = g.slot, g.mem, g.pend
    first = 0
    for q in range(ns):
        j = starts[q]
        if g.touched[j] != g.evid[0]:
            g.touched[j] = g.evid[0]
            first += 1
        i = slot[j]
        if i >= 0:
            win.slip[i] = 1
            win.v[i] = 0.0
            win.sg[i] = 1.0
            win.piece[i] = 0
        else:
            pend[j] = cnt
            tree_set(g.tv, g.ti, g.p, j, _NEG_INF)
    # members: slipping blocks and their neighbours
    k = 0
    nb = win.nblk
    for q in range(m + ns):
        if q < m:
            if not win.slip[q]:
                continue
            b = win.blk[q]
        else:
            b = starts[q - m]
            if slot[b] >= 0:
                continue
        lf, rt, _ = _neighbours(b, n, periodic)
        for c in (b, lf, rt):
            if c >= 0 and mem[c] != cnt:
                mem[c] = cnt
                nb[k] = c
                k += 1
    # state of the new members (from the old slots, the starts, or the far representation)
    for q in range(k):
        b = nb[q]
        i = slot[b]
        if i >= 0:
            win.nsg[q] = win.sg[i]
            win.nv[q] = win.v[i]
            win.nslip[q] = win.slip[i]
            win.nlt[q] = win.lt[i]
            win.npiece[q] = win.piece[i]
        elif pend[b] == cnt:
            win.nsg[q] = 1.0
            win.nv[q] = 0.0
            win.nslip[q] = 1
            win.nlt[q] = 0.0
            win.npiece[q] = 0
        else:
            win.nsg[q] = ((g.s[b] - base) + 1.0) + lam
            win.nv[q] = 0.0
            win.nslip[q] = 0
            win.nlt[q] = -1.0
            win.npiece[q] = 0
            tree_set(g.tv, g.ti, g.p, b, _NEG_INF)
    for i in range(m):   # leavers: stuck among stuck neighbours, back to the tree
        b = win.blk[i]
        if mem[b] != cnt:
            g.s[b] = ((win.sg[i] - 1.0) - lam) + base
            tree_set(g.tv, g.ti, g.p, b, g.s[b])
        slot[b] = -1
    for q in range(k):
        b = nb[q]
        slot[b] = q
        win.blk[q] = b
        win.sg[q] = win.nsg[q]
        win.d[q] = win.nsg[q] - 1.0
        win.dn[q] = win.d[q] / nu
        win.v[q] = win.nv[q]
        win.w[q] = 0.0
        win.slip[q] = win.nslip[q]
        win.lt[q] = win.nlt[q]
        win.piece[q] = win.npiece[q]
    for q in range(k):
        lf, rt, sc = _neighbours(win.blk[q], n, periodic)
        win.left[q] = slot[lf] if lf >= 0 else -1
        win.right[q] = slot[rt] if rt >= 0 else -1
        win.selfc[q] = sc
    return k, first


@_jit
def _commit(m, tau, win, g, l2, nu):
    """Fold the segment into σ (win.sg) and U; returns Σ w (the segment's slip / ν)."""
    tot = 0.0
    w = win.w
    for i in range(m):
        lf, rt = win.left[i], win.right[i]
        c = (win.selfc[i] - 2.0) * w[i]
        if lf >= 0:
            c += w[lf]
        if rt >= 0:
            c += w[rt]
        win.nsg[i] = win.sg[i] + nu * ((l2 * c - w[i]) + tau)
    for i in range(m):
        win.sg[i] = win.nsg[i]
        g.u[win.blk[i]] += nu * w[i]
        tot += w[i]
    return tot


@_jit
def _side(j, k, win, tau, l2, fr, law):
    """Piece of slot j at breakpoint k (between pieces k and k + 1): by the direction of x there."""
    slip, piece, left, right, selfc, d = win.slip, win.piece, win.left, win.right, win.selfc, win.dn
    code, consts, tstart, regs = law.code, law.consts, law.start, law.regs   # (a named tuple's field: ~400 ns per read)
    nu, sig = fr[0], fr[2]
    gb = law.g_break[k]
    if sig != 0.0:
        gb = sig + (1.0 - sig) * gb
    rate = _load(j, win.w, tau, left, right, selfc, d, l2, nu) + gb / nu
    if rate > 0.0:
        return k + 1
    if rate < 0.0:
        return k
    return win.piece[j]


@_jit
def _piece_index(law, xs):
    k = 0
    for i in range(law.lower.size):
        if xs >= law.lower[i]:
            k = i
    return k


# -- velocity-threshold crossings recorded without cutting the step (``_subevents``) -----------------
@_jit
def _xing_possible(m, win, vth, above):
    """Whether a slipping slot may cross vth over a whole step (ends, or a maximum of v inside it)."""
    for i in range(m):
        if win.slip[i]:
            if above[win.blk[i]] == 0:
                if win.v1[i] > vth or (win.kv[i, 0] > 0.0 and win.kv[i, 12] < 0.0):
                    return True
            elif win.v1[i] <= vth:
                return True
    return False


@_jit
def _xbisect(fv, v, i, vth, a, b, rising):
    """θ in (a, b] just past the crossing of vth by slot i's dense velocity (bisection to rounding)."""
    for _ in range(200):
        if b - a <= 2.2e-16 * b:
            break
        c = 0.5 * (a + b)
        if (_dense_called(fv, v, i, c) > vth) == rising:
            b = c
        else:
            a = c
    return b


@_jit
def _xrec(m, win, tau, hh, th, i, up, xbuf):
    """Row (τ, slot, up, Σ_q w_q at τ) of a crossing at θ = th of the step from τ of length hh."""
    q = int(xbuf[0, 0]) + 1
    ws = 0.0
    for r in range(m):
        ws += _dense_called(win.fw, win.w, r, th) if win.slip[r] else win.w[r]
    xbuf[q, 0] = tau + th * hh
    xbuf[q, 1] = i
    xbuf[q, 2] = up
    xbuf[q, 3] = ws
    xbuf[0, 0] = q


@_jit
def _xings(m, win, tau, hh, lim, vth, above, xbuf):
    """The crossings of vth by the slipping slots' velocities over θ ∈ [0, lim] of an accepted step, located
    on its dense output to rounding as ``_segment``'s cut kind 3 was, appended to ``xbuf`` (rows from 1,
    the count in xbuf[0, 0]; in slot order, not time order) with the flags ``above`` flipped. The step is
    not cut there: the dynamics do not depend on V_th, and cutting (a new segment, window and Taylor
    expansion at each of ~2600 crossings per event) was 56 % of the segments at mori-kawamura-2006, ν_f = 0.25."""
    fv, v, kv = win.fv, win.v, win.kv
    for i in range(m):
        if not win.slip[i]:
            continue
        b = win.blk[i]
        vb = win.v1[i] if lim >= 1.0 else _dense_called(fv, v, i, lim)
        if above[b] == 0:
            if vb > vth:
                th = 0.0 if v[i] > vth else _xbisect(fv, v, i, vth, 0.0, lim, True)
                _xrec(m, win, tau, hh, th, i, 1, xbuf)
                above[b] = 1
            elif kv[i, 0] > 0.0 and kv[i, 12] < 0.0:
                vm, thm = _vmax_at(i, win, lim)   # both ends below, a maximum inside: up and down around it
                if vm > vth:
                    _xrec(m, win, tau, hh, _xbisect(fv, v, i, vth, 0.0, thm, True), i, 1, xbuf)
                    _xrec(m, win, tau, hh, _xbisect(fv, v, i, vth, thm, lim, False), i, 0, xbuf)
        elif vb <= vth:
            th = 0.0 if v[i] <= vth else _xbisect(fv, v, i, vth, 0.0, lim, False)
            _xrec(m, win, tau, hh, th, i, 0, xbuf)
            above[b] = 0


@_jit
def _segment(m, win, g, law, gfun, fr, par, tau_far, t_left, h, acc, vth, above, xbuf=None):
    """Integrate the window from w = 0 until the event ends (0), a window block starts (1, slot),
    the far block starts (2), the bounds are reached (3) or the state is not finite (5).
    Returns (code, slot, τ, next h); ``acc`` accumulates [steps, Σ err(w), vmax].
    ``vth`` > 0 (scaled, V_th/ν; ``_threshold``): a slipping block's velocity crossing vth against its
    flag ``above[block]`` also ends the segment (6, slot); 0 leaves the engine as it is. With ``xbuf``
    (``_xings``) a crossing ends nothing: it is recorded there and the step goes on (7: the buffer is full)."""
    slip, piece, left, right, selfc, d = win.slip, win.piece, win.left, win.right, win.selfc, win.dn
    code, consts, tstart, regs = law.code, law.consts, law.start, law.regs   # (a named tuple's field: ~400 ns per read)
    w, v, w1, v1, fw, fv, tw, tv_ = win.w, win.v, win.w1, win.v1, win.fw, win.fv, win.tw, win.tv
    nu, nu_fs, l2 = fr[0], fr[1], par[0]
    rtol, atol, max_steps = par[1], par[2], par[3]
    kw, kv = win.kw, win.kv
    npieces = law.lower.size
    taylor = fw.shape[1] != 7      # the Carlson–Langer law: Taylor steps (``_taylor``), else DOP853
    tau = 0.0
    if not taylor:
        _rhs(m, w, v, tau, slip, piece, left, right, selfc, d, gfun, code, consts, tstart, regs, fr, l2, kw, kv, 0)
    else:
        for i in range(m):      # a stuck slot's Taylor rows stay zero (``_taylor`` reads a neighbour's w series)
            if not slip[i]:
                for q in range(fw.shape[1]):
                    fw[i, q] = 0.0
                    fv[i, q] = 0.0
    t_end = min(tau_far, t_left)
    h_acc, e_acc, rejected = 0.0, 0.0, False   # the last accepted step and error (predictive control)
    nslip = 0
    for i in range(m):
        nslip += slip[i]
    again = False         # this step re-takes one that straddled a stop, up to it
    while True:
        if tau >= t_end:
            return (2 if tau_far <= t_left else 3), -1, tau, h
        if xbuf is not None:
            if xbuf[0, 0] + 2 * m + 2 > xbuf.shape[0]:
                return 7, -1, tau, h
        if taylor:
            h = _taylor(m, tau, win, fr, l2, rtol, atol)
            if not (h > 1e-14 * max(1.0, tau)):
                return (5 if h != h else 3), -1, tau, h
        hh = min(h, t_end - tau)
        last = hh == t_end - tau
        if taylor:
            err, ew, ev = _taylor_step(m, hh, win, kv)
        else:
            err, ew, ev = _step(m, hh, tau, win, law, gfun, fr, l2, rtol, atol)
        if not (err <= 1.0):
            if err != err:          # NaN: a non-finite stage
                for i in range(m):
                    if not (math.isfinite(w1[i]) and math.isfinite(v1[i])):
                        if hh < 1e-12:
                            return 5, -1, tau, h
                h = 0.2 * hh
                continue
            h = hh * max(0.2, 0.9 / _root8(err))
            again = False
            rejected = True
            if h < 1e-14 * max(1.0, tau):
                return 3, -1, tau, h
            continue
        acc[0] += 1.0
        if acc[0] > max_steps:
            return 3, -1, tau, h
        fac = 10.0 if (err == 0.0 or taylor) else min(10.0, max(0.2, 0.9 / _root8(err)))
        if h_acc > 0.0 and err > 0.0 and not taylor:
            # Gustafsson's predictive controller (as in Hairer's radau5, exponent 1/8 here): the error grows
            # ~4x per step towards a stop (the continuation of v past 0 meets the pole of Φ), and the
            # standard controller then rejected every other step there (49 % of all steps, N = 64).
            # Safety 0.8, not 0.9: the steps' errors then stay where the rejections had kept them
            # (a 20-event σ_f = 0.05 run drifted from the heyoka engine's 3.5x more at 0.9)
            fac = min(fac, max(0.2, 0.8 * (hh / h_acc) * _root8(e_acc / (err * err))))
        if rejected:
            fac = min(fac, 1.0)
        h_acc, e_acc, rejected = hh, max(1e-2, err), False
        hnext = hh * fac
        # sign changes of the event functions over the step
        best, kind_b, slot_b, brk_b = 2.0, -1, -1, -1
        dense = taylor     # a Taylor step's polynomial is its dense output (and a call copies the window's arrays)
        interior = False
        for i in range(m):
            if slip[i]:
                va, vb = v[i], v1[i]
                if vb <= 0.0 and (va > 0.0 or vb < 0.0):
                    if not dense:
                        _dense_prepare(m, hh, tau, win, law, gfun, fr, l2)
                        dense = True
                    if va > 0.0:
                        th = _root(0, i, win, tau, hh, l2, nu, 0.0, va, vb)
                    else:
                        # at rest at the step's start (kept slipping at V = 0 by σ ≥ 1 to rounding): the stop is
                        # past its excursion above 0, if any, else at once. (From θ = 0, where v = 0, the root
                        # was found at 6e-61; the block kept slipping by the rounding rule below, τ crawling by
                        # such steps until max_steps: N = 64, ν = 1e-4, Taylor steps)
                        th = _past_excursion(i, win, tau, hh, l2, nu, 0.0, False)
                        if th > 1.0:
                            th = 0.0
                    if th < best:
                        best, kind_b, slot_b = th, 0, i
                pc = piece[i]
                if npieces > 1:
                    x1 = (nu * vb) / nu_fs
                    up = law.upper[pc]
                    lo = law.lower[pc]
                    bnd = -1.0
                    if x1 >= up:
                        bnd = up
                    elif x1 < lo and pc > 0:
                        bnd = lo
                    if bnd >= 0.0:
                        if not dense:
                            _dense_prepare(m, hh, tau, win, law, gfun, fr, l2)
                            dense = True
                        tv = bnd * nu_fs / nu
                        if (va - tv < 0.0) if bnd == up else (va - tv > 0.0):
                            th = _root_called(2, i, win, tau, hh, l2, nu, tv, va - tv, vb - tv)
                        else:     # at the breakpoint at the step's start (switched there)
                            th = _past_excursion(i, win, tau, hh, l2, nu, tv, bnd == up)
                            if th > 1.0:
                                th = _root_called(2, i, win, tau, hh, l2, nu, tv, va - tv, vb - tv)
                        if th < best:
                            best, kind_b, slot_b, brk_b = th, 2, i, (pc if bnd == up else pc - 1)
                if va > 0.0 and (kv[i, 0] < 0.0 < kv[i, 12] or (npieces > 1 and kv[i, 12] < 0.0 < kv[i, 0])) and \
                        (taylor or _reach(i, kv, hh, va, vb, kv[i, 0] < 0.0, nu_fs / nu, law, pc)):
                    if not dense:     # an extremum of v inside the step: an event there and back?
                        _dense_prepare(m, hh, tau, win, law, gfun, fr, l2)
                        dense = True
                    th, kd, bk = _inside(i, win, tau, hh, l2, nu, nu_fs, law, pc, kv[i, 0] < 0.0)
                    if th < best:
                        best, kind_b, slot_b, brk_b = th, kd, i, bk
                if kv[i, 0] > 0.0 and kv[i, 12] < 0.0:
                    interior = True
                if vth > 0.0 and xbuf is None:
                    isup = above[win.blk[i]] == 0
                    fa_t, fb_t = va - vth, vb - vth
                    if isup and fb_t <= 0.0 and kv[i, 0] > 0.0 and kv[i, 12] < 0.0:
                        # both ends below, a maximum inside: if it exceeds vth, the up-crossing lies
                        # before it (bisection on the dense output between the start and the maximum)
                        if not dense:
                            _dense_prepare(m, hh, tau, win, law, gfun, fr, l2)
                            dense = True
                        vm, thm = _vmax_at(i, win, 1.0)
                        if vm > vth and thm < best:
                            a_, b_ = 0.0, thm
                            for _ in range(200):
                                if b_ - a_ <= 2.2e-16 * b_:
                                    break
                                c_ = 0.5 * (a_ + b_)
                                if _dense(fv, v, i, c_) > vth:
                                    b_ = c_
                                else:
                                    a_ = c_
                            if b_ < best:
                                best, kind_b, slot_b = b_, 3, i
                    elif (isup and fb_t > 0.0) or (not isup and fb_t <= 0.0):
                        if (isup and fa_t > 0.0) or (not isup and fa_t <= 0.0):
                            th = 0.0            # already across at the step's start (rounding of the cut)
                        else:
                            if not dense:
                                _dense_prepare(m, hh, tau, win, law, gfun, fr, l2)
                                dense = True
                            th = _root_called(2, i, win, tau, hh, l2, nu, vth, fa_t, fb_t)
                        if th < best:
                            best, kind_b, slot_b = th, 3, i
            else:
                f0 = _load(i, w, tau, left, right, selfc, d, l2, nu)
                if f0 < 0.0:
                    f1 = _load(i, w1, tau + hh, left, right, selfc, d, l2, nu)
                    if f1 >= 0.0:
                        if not dense:
                            _dense_prepare(m, hh, tau, win, law, gfun, fr, l2)
                            dense = True
                        th = _root(1, i, win, tau, hh, l2, nu, 0.0, f0, f1)
                        if th < best:
                            best, kind_b, slot_b = th, 1, i
        if kind_b >= 0:     # a start before the step's first event (σ_i need not be monotone past it)
            jb = slot_b if kind_b == 1 else -1
            for i in range(m):
                if not slip[i] and i != jb and _load(i, w, tau, left, right, selfc, d, l2, nu) < 0.0:
                    th = _start_before(i, win, tau, hh, l2, nu, best)
                    if th < best:
                        best, kind_b, slot_b = th, 1, i
        if kind_b == 0 and best < 1.0 and not again and par[7] != 0.0:
            # friction that fades (par[7]), a stop inside the step: take the step again, to 1 % past it.
            # Past the stop the stages follow v < 0 and need not see friction's steep rise near v = 0
            # (exp(-x-4x^2), σ_f = 0.9: 1e-6 off, error estimate 1e-12); the new step's last stages are next
            # to v = 0. (Exactly to the stop, it often ended just short of it: the next step again, steps
            # shrinking to 1e-31.) Algebraic and piecewise laws agree without it (random chains, σ_f < 0.999).
            acc[0] -= 1.0
            h = 1.01 * best * hh
            again = True
            continue
        again = False
        lim = 1.0 if kind_b < 0 else best
        if interior:
            if not dense:
                _dense_prepare(m, hh, tau, win, law, gfun, fr, l2)
                dense = True
            for i in range(m):
                if slip[i] and kv[i, 0] > 0.0 and kv[i, 12] < 0.0:
                    acc[2] = max(acc[2], _vmax_in(i, win, lim))
        # the step's own displacement error, and what the velocity errors of the event's earlier steps
        # (acc[3], their sum) add to the displacement over this step: w' = v carries a velocity error on
        # (the last term of w alone under-estimated the Taylor path's error 2.7-10x: tests/test_chain_error_estimate.py)
        acc[1] += ew + acc[3] * hh
        acc[3] += ev
        if xbuf is not None:
            if vth > 0.0:
                if not dense and _xing_possible(m, win, vth, above):
                    _dense_prepare(m, hh, tau, win, law, gfun, fr, l2)
                    dense = True
                if dense:
                    _xings(m, win, tau, hh, lim, vth, above, xbuf)
        if kind_b < 0:     # no event: take the whole step (FSAL)
            for i in range(m):
                w[i] = w1[i]
                v[i] = v1[i]
                kw[i, 0] = kw[i, 12]
                kv[i, 0] = kv[i, 12]
                if slip[i] and v[i] > acc[2]:
                    acc[2] = v[i]
            tau = t_end if last else tau + hh
            h = hnext
            continue
        # cut the step at the event
        tau0 = tau
        if best >= 1.0:
            for i in range(m):
                w[i] = w1[i]
                v[i] = v1[i]
            tau = t_end if last else tau + hh
        else:
            for i in range(m):     # both from the step's start state, then written (a stuck slot's: its state)
                if slip[i]:
                    tw[i] = _dense(fw, w, i, best)
                    tv_[i] = _dense(fv, v, i, best)
                else:
                    tw[i] = w[i]
                    tv_[i] = v[i]
            for i in range(m):
                w[i] = tw[i]
                v[i] = tv_[i] if slip[i] else 0.0
            tau = tau + best * hh
        for i in range(m):
            if slip[i] and v[i] > acc[2]:
                acc[2] = v[i]
        h = hnext
        j = slot_b
        if kind_b == 1:
            return 1, j, tau, h
        if kind_b == 3:                     # a velocity-threshold crossing
            return 6, j, tau, h
        if kind_b == 0:
            for i in range(m):
                if slip[i] and (i == j or v[i] <= 0.0):
                    v[i] = 0.0
                    if tau > tau0 and _load(i, w, tau, left, right, selfc, d, l2, nu) >= 0.0:
                        continue             # σ ≥ 1 at V = 0 (rounding): it cannot stick
                    # (a block kept at V = 0 that decelerates at once stops at the step's start, τ not
                    # advancing: σ − 1 is at rounding level there; keeping it looped forever, found at
                    # event 63 944 of N = 1024, ν = 1e-4, seed 1)
                    slip[i] = 0
                    nslip -= 1
                    if taylor:
                        for q in range(fw.shape[1]):
                            fw[i, q] = 0.0
                            fv[i, q] = 0.0
            if nslip == 0:
                return 0, -1, tau, h
        else:
            piece[j] = _side(j, brk_b, win, tau, l2, fr, law)
            for i in range(m):     # coincident crossings (as ``ChainLoop._switches``)
                if i != j and slip[i]:
                    xs = (nu * v[i]) / nu_fs
                    p0 = piece[i]
                    if xs < law.lower[p0] or xs > law.upper[p0]:
                        new = _piece_index(law, xs)
                        if abs(new - p0) == 1:
                            new = _side(i, min(new, p0), win, tau, l2, fr, law)
                        piece[i] = new
        if not taylor:
            _rhs(m, w, v, tau, slip, piece, left, right, selfc, d, gfun, code, consts, tstart, regs, fr, l2, kw, kv, 0)


# -- the lone block's stored trajectory (``_lone``) ----------------------------------------------------
_EPS = 2.220446049250313e-16


@_inline
def _horner(c, i, x):
    kk = c.shape[1]
    y = c[i, kk - 1]
    for q in range(kk - 2, -1, -1):
        y = y * x + c[i, q]
    return y


@_jit
def _lone_step(lone, a, b, tau):
    """The stored step of [a, b) holding τ (the last one with t0 ≤ τ)."""
    lo, hi = a, b - 1
    while lo < hi:
        mid = (lo + hi + 1) >> 1
        if lone.t0[mid] <= tau:
            lo = mid
        else:
            hi = mid - 1
    return lo


@_jit
def _lone_root(lone, a, b, dn, l2):
    """τ where a stuck neighbour's (σ − 1)/ν = dn + ℓ² w(τ) + τ reaches 0 (it is < 0 at τ = 0 and ≥ 0
    at the stop; increasing, its derivative ℓ² v + 1 ≥ 1): the step by bisection over the steps' start
    values, then safeguarded Newton on its polynomial, to rounding."""
    lo, hi = a, b - 1
    while lo < hi:                     # the last step whose start is below the threshold
        mid = (lo + hi + 1) >> 1
        if dn + l2 * lone.cw[mid, 0] + lone.t0[mid] < 0.0:
            lo = mid
        else:
            hi = mid - 1
    i = lo
    t0 = lone.t0[i]
    xl, xr = 0.0, lone.t1[i] - t0
    x = xr
    fx = dn + l2 * _horner(lone.cw, i, x) + (t0 + x)
    if fx < 0.0:
        return lone.t1[i], i
    x = 0.5 * xr
    for _ in range(100):
        fx = dn + l2 * _horner(lone.cw, i, x) + (t0 + x)
        if fx < 0.0:
            xl = x
        else:
            xr = x
        if fx == 0.0:
            break
        xn = x - fx / (l2 * _horner(lone.cv, i, x) + 1.0)
        if not (xl < xn < xr):
            xn = 0.5 * (xl + xr)
        if abs(xn - x) <= 4.0 * _EPS * (t0 + x) or xn == x:
            break
        x = xn
    # a tight bracket around the root (Newton converged next to it), then bisection to rounding: the
    # result is the first point where the threshold is reached, as ``_root`` for DOP853
    dl = 8.0 * _EPS * (t0 + x)
    if xl < x - dl and dn + l2 * _horner(lone.cw, i, x - dl) + (t0 + x - dl) < 0.0:
        xl = x - dl
    if x + dl < xr and dn + l2 * _horner(lone.cw, i, x + dl) + (t0 + x + dl) >= 0.0:
        xr = x + dl
    for _ in range(200):
        c = 0.5 * (xl + xr)
        if not (xl < c < xr):
            break
        if dn + l2 * _horner(lone.cw, i, c) + (t0 + c) < 0.0:
            xl = c
        else:
            xr = c
    x = xr
    return t0 + x, i


@_jit
def _lone_w(lone, a, b, th):
    if th <= 0.0:
        return 0.0
    st = _lone_step(lone, a, b, th)
    return _horner(lone.cw, st, th - lone.t0[st])


@_jit
def _lone_state(lone, a, b, kind, th0, th, acc):
    """(w since the segment start, v, piece, stopped) of a lone block at its own time th since its start,
    the segment having started at th0; accumulates its velocity maximum and error estimate in acc."""
    T = lone.sc[kind, 0]
    if th >= T:
        acc[2] = max(acc[2], lone.sc[kind, 2])
        acc[1] += (b - a) * _EPS * lone.sc[kind, 1]
        return lone.sc[kind, 1] - _lone_w(lone, a, b, th0), 0.0, 0, True
    st = _lone_step(lone, a, b, th)
    x = th - lone.t0[st]
    wv = _horner(lone.cw, st, x)
    vv = max(_horner(lone.cv, st, x), 0.0)
    vm = max(lone.pre[st], vv)
    if 0.0 <= lone.imt[st] <= x:
        vm = max(vm, lone.imv[st])
    acc[2] = max(acc[2], vm)
    acc[1] += (st - a + 1) * _EPS * wv
    return wv - _lone_w(lone, a, b, th0), vv, lone.piece[st], False


@_inline
def _lone_segment(m, win, lone, l2, tau_far, t_left, acc):
    """A segment in which every slipping block is a lone block on the stored trajectory (started from
    rest among stuck neighbours, ``win.lt`` its time since then; no two of them neighbours, no stuck
    block between two of them): (code, slot, τ) as ``_segment`` (0 every one stopped, 1 a window block
    starts, 2 the far block starts), the window's state written at τ and ``win.lt`` advanced; code −1
    if it does not apply (then nothing was written).

    A stuck window block's (σ − 1)/ν is d/ν + ℓ²(W(θ + τ) − W(θ)) + τ next to a lone block at its time
    θ (d/ν + ℓ²(W_T − W(θ)) + τ once that one stopped), d/ν + τ otherwise: increasing in τ, so its start
    is a root on the stored polynomial or in closed form."""
    ns = 0
    for i in range(m):
        lf, rt = win.left[i], win.right[i]
        if win.slip[i]:
            ns += 1
            if win.lt[i] < 0.0 or lone.sc[int(win.selfc[i]), 4] == 0.0:
                return -1, -1, 0.0
            if (lf >= 0 and win.slip[lf]) or (rt >= 0 and win.slip[rt]):
                return -1, -1, 0.0
            if win.lt[i] >= lone.sc[int(win.selfc[i]), 0]:
                return -1, -1, 0.0
        elif lf >= 0 and rt >= 0 and lf != rt and win.slip[lf] and win.slip[rt]:
            return -1, -1, 0.0
    if ns == 0:
        return -1, -1, 0.0
    tau, code, slot = 0.0, 0, -1
    for i in range(m):                      # the last stop
        if win.slip[i]:
            tau = max(tau, lone.sc[int(win.selfc[i]), 0] - win.lt[i])
    for i in range(m):                      # the first start of a stuck window block
        if win.slip[i]:
            continue
        lf, rt = win.left[i], win.right[i]
        j = lf if (lf >= 0 and win.slip[lf]) else (rt if (rt >= 0 and win.slip[rt]) else -1)
        dn = win.dn[i]
        if j < 0:
            ti = -dn
        else:
            kind = int(win.selfc[j])
            a, b = lone.off[kind], lone.off[kind + 1]
            T, W = lone.sc[kind, 0], lone.sc[kind, 1]
            th0 = win.lt[j]
            w0 = _lone_w(lone, a, b, th0)
            if dn + l2 * (W - w0) + (T - th0) >= 0.0:      # before its lone neighbour stops
                if th0 == 0.0:
                    th, _ = _lone_root(lone, a, b, dn, l2)
                else:
                    th, _ = _lone_root(lone, a, b, (dn - l2 * w0) - th0, l2)
                ti = th - th0
            else:
                ti = -(dn + l2 * (W - w0))
        if ti < tau:
            tau, code, slot = ti, 1, i
    if tau_far < tau:
        tau, code, slot = tau_far, 2, -1
    if t_left < tau:
        return -1, -1, 0.0
    for i in range(m):
        if not win.slip[i]:
            continue
        kind = int(win.selfc[i])
        a, b = lone.off[kind], lone.off[kind + 1]
        th0 = win.lt[i]
        th = th0 + tau
        if code == 0 and th0 + tau >= lone.sc[kind, 0] * (1.0 - 4.0 * _EPS):
            th = lone.sc[kind, 0]                       # the last stop: exactly at the stored one
        wv, vv, pc, stopped = _lone_state(lone, a, b, kind, th0, th, acc)
        win.w[i] = wv
        win.v[i] = vv
        if stopped or code == 0:
            win.slip[i] = 0
            win.v[i] = 0.0
            win.lt[i] = -1.0
        else:
            win.piece[i] = pc
            win.lt[i] = th
    return code, slot, tau

# -- an event's opening, failures, far block and close: shared by run_events and _subevents.run_subevents
@_inline
def _event_open(g, scal, n, nu):
    """A new event: its id, the load folded into s when |L| > 1 (O(N), once per loading cycle), the
    hypocentre (the most stressed block), its s and the event's start time. Returns (hyp, base, t_start)."""
    g.evid[0] += 1
    if abs(scal[1]) > 1.0:
        for j in range(n):
            g.s[j] += scal[1]
            g.tv[j] = g.s[j]
        tree_build(g.tv, g.ti, g.p)
        scal[1] = 0.0
    hyp = g.ti[1]
    base = g.s[hyp]
    jump = 1.0 - (base + scal[1])
    return hyp, base, scal[0] + jump / nu


@_inline
def _start_failures(m, win, g, starts, ns, base, lam, n, periodic, cnt, nu, again):
    """Start the blocks of ``starts`` and every other block at σ ≥ 1 (simultaneous failures) until none is
    left; ``again``: rebuild the window once even with no start. Returns (m, cnt, blocks new to the event)."""
    new = 0
    while ns > 0 or again:
        again = False
        cnt += 1
        m, first = _rebuild(m, win, g, starts, ns, base, lam, n, periodic, cnt, nu)
        new += first
        ns = 0
        for i in range(m):
            if not win.slip[i] and win.sg[i] >= 1.0:
                starts[ns] = win.blk[i]
                ns += 1
        top = g.ti[1]
        if g.tv[top] > _NEG_INF and ((g.s[top] - base) + 1.0) + lam >= 1.0:
            starts[ns] = top
            ns += 1
    return m, cnt, new


@_inline
def _far(g, base, lam, nu):
    """The most stressed block outside the window and the time until it fails (inf: none outside)."""
    top = g.ti[1]
    tau_far = np.inf
    if g.tv[top] > _NEG_INF:
        tau_far = (1.0 - (((g.s[top] - base) + 1.0) + lam)) / nu
    return top, tau_far


@_inline
def _event_close(m, win, g, scal, base, lam, t_end, h):
    """Event over: every window block back to the tree (σ_j = s_j + L between events), the time and step."""
    scal[1] = (1.0 - base) + lam
    for i in range(m):
        b = win.blk[i]
        g.s[b] = win.sg[i] - scal[1]
        tree_set(g.tv, g.ti, g.p, b, g.s[b])
        g.slot[b] = -1
    scal[0] = t_end
    scal[2] = min(h, 1.0)


@_jit
def run_events(k, win, g, law, gfun, fr, par, scal, out_f, out_i, lone):
    """Up to k events. ``scal`` = [t, L, h]; out_f[:, e] = t_start, potency, duration, vmax (scaled),
    error estimate; out_i[:, e] = hypocentre, n_blocks, steps, widest window. ``lone``: the stored
    lone-block trajectories (``_lone``; the event's first segment follows them when its hypocentre
    slips alone, ``par[6]`` ≠ 0). Returns (events done, outcome code)."""
    n, periodic = g.s.size, par[4] != 0.0
    nu, l2, t_max = fr[0], par[0], par[5]
    acc = scal[3:7]
    for e in range(k):
        hyp, base, t_start = _event_open(g, scal, n, nu)
        lam = 0.0
        dur = 0.0
        pot = 0.0
        acc[:] = 0.0
        m = 0
        nbl = 0
        widest = 0
        cnt = g.cnt[0]
        starts = win.starts
        starts[0] = hyp
        ns = 1
        h = scal[2]
        code = 0
        first_seg = par[6] != 0.0
        while True:
            m, cnt, first = _start_failures(m, win, g, starts, ns, base, lam, n, periodic, cnt, nu, False)
            nbl += first
            ns = 0
            widest = max(widest, m)
            top, tau_far = _far(g, base, lam, nu)
            code = -1
            if first_seg:
                code, j, tau = _lone_segment(m, win, lone, l2, tau_far, t_max - dur, acc)
            if code < 0:
                first_seg = False               # DOP853 for the rest of the event
                for i in range(m):
                    win.lt[i] = -1.0
                code, j, tau, h = _segment(m, win, g, law, gfun, fr, par, tau_far, t_max - dur, h, acc, 0.0, g.evid)
            if code == 5 or code == 3:
                break
            pot += nu * _commit(m, tau, win, g, l2, nu)
            lam += nu * tau
            dur += tau
            for i in range(m):
                win.w[i] = 0.0
            if code == 0:
                break
            starts[0] = win.blk[j] if code == 1 else top
            ns = 1
        g.cnt[0] = cnt
        if code == 3 or code == 5:
            return e, code
        _event_close(m, win, g, scal, base, lam, t_start + dur, h)
        out_f[0, e] = t_start
        out_f[1, e] = pot
        out_f[2, e] = dur
        out_f[3, e] = acc[2]
        out_f[4, e] = nu * acc[1] / pot if pot > 0.0 else 0.0
        out_i[0, e] = hyp
        out_i[1, e] = nbl
        out_i[2, e] = int(acc[0])
        out_i[3, e] = widest
    return k, 1


# -- the Python side -----------------------------------------------------------------------------------
_Law = namedtuple("_Law", "code consts start regs cl lower upper g_break")
_Win = namedtuple("_Win", "blk left right selfc sg d dn slip piece w v w1 v1 tw tv kw kv fw fv "
                          "nblk nsg nv nslip npiece starts lt nlt cr")
_Glob = namedtuple("_Glob", "s u tv ti p slot mem pend touched evid cnt")

#: DOP853's tolerance (relative, and absolute on the scaled variables, which are O(1) at a start).
#: ``--verify`` finds times and potencies within ~tol of the heyoka engine's (measured at N = 256, nu = 1e-4:
#: 6.7e-13, 1.2e-11, 1.1e-10 at tol 1e-12, 1e-11, 1e-10; docs/chain.md, "Engines")
TOL = 1e-11
#: CPU seconds of compiling ``run_events`` for one law kind with a cold disk cache, for the CLI's notice:
#: a 10-event `bifurcation chain --engine compiled` (N = 16) took 43.0–44.8 s of CPU with NUMBA_CACHE_DIR
#: an empty directory and 1.1–1.5 s with it filled, Carlson–Langer and exp(−x) alike (2026-11-26; wall time
#: 55–88 s at load 4–5 on 2 cores; docs/chain.md, "Engines"); since _dense and _root are called, not
#: inlined, at their cold sites (2026-11-26 12:30), a one-event run's compile 32.9 and 31.6 s against 46.0 and 42.4
COMPILE_SECONDS = 33


class CompiledChain:
    """One chain run on the compiled engine: the state between events and ``run(k)``.

    Same arguments as ``ChainLoop`` (double precision only) plus ``sigma`` (friction drop σ_f ≥ 0)
    and ``tol`` (DOP853's or the Taylor method's tolerance). ``lone``: follow the stored lone-block trajectory
    (``_lone``) in an event's first segment where it applies (False: integrate throughout, for comparisons).
    ``taylor``: the Taylor method (``_taylor``) for the Carlson–Langer law (False: DOP853, for comparisons)."""

    def __init__(self, law, n: int, ell: float, nu: float, nu_f: float, ends: str, u0, *, sigma: float = 0.0,
                 tol: float = TOL, t_max: float = 1e5, max_steps: int = 1_000_000, lone: bool = True,
                 taylor: bool = True) -> None:
        from ...laws._fading import ladder
        from ._lawtape import law_tape
        from ._validate import stress

        tape = law_tape(law)
        self.law, self.n, self.ends = law, n, ends
        self.nu, self.nu_f, self.ell, self.sigma = float(nu), float(nu_f), float(ell), float(sigma)
        # the law's kind as a type (``g_law``): the loop is compiled once per law kind and cached on
        # disk, and the Carlson–Langer loop holds no tape code (a single loop with both ran ~5x slower,
        # measured)
        self._gfun = CarlsonLanger() if tape.carlson_langer else Tape()
        self._law = _Law(tape.code, tape.consts, tape.start, np.zeros(max(tape.registers, 1)),
                         bool(tape.carlson_langer), tape.lower, tape.upper, tape.g_break)
        u = np.array(u0, dtype=np.float64)
        p = 1 << max(n - 1, 0).bit_length()
        s = stress(u, ell, ends)
        tv = np.full(p, -np.inf)
        tv[:n] = s
        ti = np.zeros(2 * p, dtype=np.int64)
        tree_build(tv, ti, p)
        self._g = _Glob(s, u, tv, ti, p, np.full(n, -1, dtype=np.int64), np.zeros(n, dtype=np.int64),
                        np.zeros(n, dtype=np.int64), np.zeros(n, dtype=np.int64), np.zeros(1, dtype=np.int64),
                        np.zeros(1, dtype=np.int64))
        f, i8 = np.zeros, np.int64
        taylor = bool(tape.carlson_langer) and taylor
        self.taylor = taylor
        nd = TAYLOR_ORDER if taylor else 7     # dense-output columns: Taylor coefficients or DOP853's rows
        self._win = _Win(f(n, i8), f(n, i8), f(n, i8), f(n), f(n), f(n), f(n), f(n, np.uint8), f(n, i8), f(n), f(n),
                         f(n), f(n), f(n), f(n), f((n, 16)), f((n, 16)), f((n, nd)), f((n, nd)),
                         f(n, i8), f(n), f(n), f(n, np.uint8), f(n, i8), f(n + 1, i8), np.full(n, -1.0),
                         np.full(n, -1.0), f((n, TAYLOR_ORDER + 1) if taylor else (1, 1)))
        nu_fs = self.nu_f * (1.0 - self.sigma)
        self._fr = np.array([self.nu, nu_fs, self.sigma, self.nu / nu_fs, 1.0 / self.nu])
        self._par = np.array([self.ell * self.ell, tol, tol, float(max_steps), float(ends == "periodic"),
                              float(t_max), float(bool(lone)), float(bool(ladder(law, "double").rungs))])
        from ._lone import lone_tables

        self._lone = lone_tables(law, n, ends, self.nu, self.nu_f, self.ell, self.sigma) if lone else \
            lone_tables(law, 0, "periodic", self.nu, self.nu_f, self.ell, self.sigma)
        self._scal = np.array([0.0, 0.0, 0.1, 0.0, 0.0, 0.0, 0.0])    # t, L, the next event's first step
        self.t_max, self.max_steps = t_max, max_steps
        self.widest: list[int] = []

    def compiled(self) -> bool:
        """Whether ``run`` can start without compiling: ``run_events`` for this law kind is compiled in this
        process or stored in numba's disk cache (the first run compiles it otherwise, ~COMPILE_SECONDS).
        Reads numba's cache index (not a public API): True if that fails (then at worst no notice)."""
        try:
            args = (1, self._win, self._g, self._law, self._gfun, self._fr, self._par, self._scal,
                    np.zeros((5, 1)), np.zeros((4, 1), dtype=np.int64), self._lone)
            sig = tuple(run_events.typeof_pyval(a) for a in args)
            if sig in run_events.overloads:
                return True
            if not _CACHE:
                return False
            cache = run_events._cache
            return cache._index_key(sig, run_events.targetctx.codegen()) in cache._cache_file._load_index()
        except Exception:   # noqa: BLE001 (numba internals changed: no notice rather than an error)
            return True

    @property
    def t(self) -> float:
        return float(self._scal[0])

    @property
    def u(self) -> np.ndarray:
        return self._g.u

    @property
    def stress(self) -> np.ndarray:
        """σ_j between events (s_j + L)."""
        return self._g.s + self._scal[1]

    def run(self, k: int) -> dict:
        """The next k events: dict(catalog (arrays), status, message), as ``ChainLoop.run``."""
        from .result import ChainStatus

        out_f = np.zeros((5, k))
        out_i = np.zeros((4, k), dtype=np.int64)
        done, code = run_events(k, self._win, self._g, self._law, self._gfun, self._fr, self._par, self._scal, out_f, out_i,
                                self._lone)
        cat = {"t_start": out_f[0, :done].copy(), "hypocentre": out_i[0, :done].copy(),
               "n_blocks": out_i[1, :done].copy(), "potency": out_f[1, :done].copy(),
               "duration": out_f[2, :done].copy(), "max_velocity": self.nu * out_f[3, :done],
               "steps": out_i[2, :done].copy(), "error_estimate": out_f[4, :done].copy()}
        self.widest += out_i[3, :done].tolist()
        status, message = ChainStatus.COMPLETE, ""
        if code == NO_STOP:
            status = ChainStatus.NO_STOP
            message = (f"event {done} did not end before t_max = {self.t_max:g} or max_steps = "
                       f"{self.max_steps} (or its step size underflowed)")
        elif code == NONFINITE:
            status, message = ChainStatus.NONFINITE, f"non-finite state in event {done}"
        return dict(catalog=cat, status=status, message=message)

    def restore(self, sigma, u, t) -> None:
        """Set a between-events state (σ, U, t), as ``snapshot`` returns it."""
        g = self._g
        g.s[:] = sigma
        g.u[:] = u
        g.tv[:self.n] = g.s
        tree_build(g.tv, g.ti, g.p)
        self._scal[0], self._scal[1] = float(t), 0.0

    def snapshot(self) -> tuple[np.ndarray, np.ndarray, float]:
        """(σ, U, t) now: a between-events state (every block stuck)."""
        return self.stress.copy(), self._g.u.copy(), self.t


def run_verified(run: CompiledChain, k: int, fraction: float, *, echo=None) -> tuple[dict, dict]:
    """``run.run(k)`` with every ⌈1/fraction⌉-th event (the first included) run again by the heyoka
    engine from the same pre-event state (σ, U, t). Returns (the run's output, the largest
    differences: |Δ| / max(1, |x|) of t_start, potency, duration, max_velocity, and the events whose
    hypocentre or size differ)."""
    from ._loop import ChainLoop

    every = max(1, int(math.ceil(1.0 / fraction - 1e-9)))
    parts, done = [], 0
    worst = {"t_start": 0.0, "potency": 0.0, "duration": 0.0, "max_velocity": 0.0}
    mismatched, checked, status, message = [], 0, None, ""
    while done < k:
        sigma, u, t = run.snapshot()
        out = run.run(1)
        parts.append(out["catalog"])
        status, message = out["status"], out["message"]
        if out["catalog"]["potency"].size == 0:
            break
        loop = ChainLoop(run.law, run.n, run.ell, run.nu, run.nu_f, run.ends, u, t_max=run.t_max,
                         max_steps=run.max_steps, drop=run.sigma)
        loop.sigma[:] = sigma
        loop.t = np.float64(t)
        ref = loop.run(1)["catalog"]
        checked += 1
        c = out["catalog"]
        if ref["hypocentre"][0] != c["hypocentre"][0] or ref["n_blocks"][0] != c["n_blocks"][0]:
            mismatched.append(done)
        else:
            for f in worst:
                a, b = float(c[f][0]), float(ref[f][0])
                worst[f] = max(worst[f], abs(a - b) / max(1.0, abs(b)))
        done += 1
        if done < k:
            m = min(every - 1, k - done)
            if m:
                out = run.run(m)
                parts.append(out["catalog"])
                status, message = out["status"], out["message"]
                done += out["catalog"]["potency"].size
                if out["catalog"]["potency"].size < m:
                    break
    cat = {f: np.concatenate([p[f] for p in parts]) for f in parts[0]}
    report = {"checked": checked, "every": every, "mismatched": mismatched, "largest": worst,
              "largest_any": max(worst.values())}
    return dict(catalog=cat, status=status, message=message), report
