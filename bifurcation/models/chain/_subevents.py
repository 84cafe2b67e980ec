"""Events split in time by a slip-velocity threshold, on the compiled engine (docs/chain.md, "Event
membership", "Split in time").

The compiled engine's event runs until every block is stuck; at a published loading rate (ν = 0.01)
a long chain is never all stuck, so that event never ends. Here the same dynamics (``_compiled``'s
windows, DOP853 and located stops and starts) are followed through such a stretch, and the catalog
is cut in time instead: an event opens when some block's velocity V exceeds V_th and closes when no
block exceeds it. Every crossing V_j = V_th is located on DOP853's dense output to rounding (a new
root kind in ``_segment``; a crossing up and down inside one step is caught by maximising V_j on the
step when both ends are below). Per event: its opening time, the first block above V_th (the
hypocentre), its duration, the blocks that exceeded V_th (``n_blocks``) and the potency: the slip
of *every* block during the open interval (blocks below V_th move too, slowly). Slip while no block
exceeds V_th is summed apart (``below_slip``), so the catalog says how much slip it leaves out.

The lone-block shortcut of ``_compiled`` is not used (its stored trajectory has no crossing roots),
so a catalog costs what the engine costs with ``lone=False``. The run stops after ``k`` events,
possibly inside an all-stuck stretch (its state is kept, so the next ``run`` goes on from there).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ._compiled import (_DEPENDS, NO_STOP, NONFINITE, CompiledChain, _commit, _event_close, _event_open, _far,
                        _segment, _start_failures)
from ._numba_cache import jit

#: numba checks a cached function against its own file only, and ``run_subevents`` holds ``_compiled``'s
#: ``_segment`` compiled in: so its cache also goes stale when ``_compiled.py`` (or what that depends on) changes
_jit = jit(depends=[*_DEPENDS, Path(__file__).with_name("_compiled.py")], nogil=True, error_model="numpy", _nrt=False)

__all__ = ["SubeventRun", "run_subevents"]

#: outcome codes as run_events
COMPLETE = 1


@_jit
def _xsort(xbuf, nx):
    """Rows 1..nx of xbuf by time (insertion sort: the rows of one step are in slot order, steps in time order)."""
    for q in range(2, nx + 1):
        r0, r1, r2, r3 = xbuf[q, 0], xbuf[q, 1], xbuf[q, 2], xbuf[q, 3]
        p = q - 1
        while p >= 1 and xbuf[p, 0] > r0:
            xbuf[p + 1, 0], xbuf[p + 1, 1], xbuf[p + 1, 2], xbuf[p + 1, 3] = xbuf[p, 0], xbuf[p, 1], xbuf[p, 2], xbuf[p, 3]
            p -= 1
        xbuf[p + 1, 0], xbuf[p + 1, 1], xbuf[p + 1, 2], xbuf[p + 1, 3] = r0, r1, r2, r3


@_jit
def run_subevents(k, win, g, law, gfun, fr, par, scal, vth, above, stamp, out_f, out_i, tot, t_stop, every, ctx,
                  xbuf):
    """Up to k threshold events, or until the time t_stop (then possibly inside a stretch, its state kept
    in ``ctx`` so the next call goes on from there); a progress line on stdout every ``every`` events
    (0: none). out_f[:, e] = t_start, potency, duration; out_i[:, e] = hypocentre, n_blocks. ``tot``
    accumulates [all-stuck stretches ended, slip below V_th, slip in events, steps, largest window].
    ``vth`` is V_th/ν. ``xbuf``: the crossings of a segment (``_compiled._xings``, rows from 1); a segment can
    close several events, so out_f/out_i need room for k − 1 + (rows of xbuf) events and more than k may be
    returned (``SubeventRun.run`` keeps the surplus for the next call). Returns (events done, outcome code)."""
    n, periodic = g.s.size, par[4] != 0.0
    nu, l2, t_max = fr[0], par[0], par[5]
    acc = scal[3:7]      # [steps, Σ err, vmax, Σ err(v)] in the scalars: the engine compiles without numba's allocator (_nrt=False)
    nsub = 0
    sub_id = stamp[n]           # the last event's id (stamps of its member blocks)
    while nsub < k:
        if ctx[0] != 0.0:       # resume inside a stretch
            ctx[0] = 0.0
            base, lam, dur, t_start = ctx[1], ctx[2], ctx[3], ctx[4]
            m, cnt, h, nab = int(ctx[5]), int(ctx[6]), ctx[7], int(ctx[8])
            sub_open, sub_t0, sub_pot = ctx[9] != 0.0, ctx[10], ctx[11]
            sub_nbl, sub_hyp, ns, refresh = int(ctx[12]), int(ctx[13]), int(ctx[14]), ctx[15] != 0.0
            starts = win.starts
            acc[:] = 0.0
        else:
            hyp, base, t_start = _event_open(g, scal, n, nu)
            if t_start >= t_stop:
                return nsub, COMPLETE
            lam = 0.0
            dur = 0.0
            acc[:] = 0.0
            m = 0
            cnt = g.cnt[0]
            starts = win.starts
            starts[0] = hyp
            ns = 1
            h = scal[2]
            nab = 0                 # blocks above V_th now
            sub_open = False
            sub_t0 = 0.0
            sub_pot = 0.0
            sub_nbl = 0
            sub_hyp = -1
            refresh = False
        code = 0
        while True:
            # (after a crossing, ``refresh`` with no starts: the segment constants d/ν from σ)
            m, cnt, _ = _start_failures(m, win, g, starts, ns, base, lam, n, periodic, cnt, nu, refresh)
            ns = 0
            refresh = False
            if m > tot[4]:
                tot[4] = m
            top, tau_far = _far(g, base, lam, nu)
            for i in range(m):
                win.lt[i] = -1.0
            code, j, tau, h = _segment(m, win, g, law, gfun, fr, par, tau_far, t_max - dur, h, acc, vth, above, xbuf)
            if code == 5 or code == 3:
                break
            wseg = _commit(m, tau, win, g, l2, nu)
            nx = int(xbuf[0, 0])
            xbuf[0, 0] = 0.0
            _xsort(xbuf, nx)
            wdone = 0.0
            for q in range(1, nx + 2):       # the crossings in time order, then the segment's end
                if q <= nx:
                    tq, b, wq = xbuf[q, 0], win.blk[int(xbuf[q, 1])], xbuf[q, 3]
                else:
                    tq, b, wq = tau, -1, wseg
                part = nu * (wq - wdone)
                wdone = wq
                if sub_open:
                    sub_pot += part
                    tot[2] += part
                else:
                    tot[1] += part
                if q > nx:
                    # a block that stopped while flagged above (a stop and a crossing at one rounding) is below
                    for i in range(m):
                        bb = win.blk[i]
                        if above[bb] != 0 and not win.slip[i]:
                            above[bb] = 0
                            nab -= 1
                elif xbuf[q, 2] != 0.0:
                    nab += 1
                    if not sub_open:
                        sub_open = True
                        sub_id += 1
                        sub_t0 = t_start + (dur + tq)
                        sub_pot = 0.0
                        sub_nbl = 0
                        sub_hyp = b
                    if stamp[b] != sub_id:
                        stamp[b] = sub_id
                        sub_nbl += 1
                else:
                    nab -= 1
                if sub_open and nab == 0:
                    out_f[0, nsub] = sub_t0
                    out_f[1, nsub] = sub_pot
                    out_f[2, nsub] = (t_start + (dur + tq)) - sub_t0
                    out_i[0, nsub] = sub_hyp
                    out_i[1, nsub] = sub_nbl
                    nsub += 1
                    sub_open = False
                    if every > 0 and nsub % every == 0:
                        print("  events", nsub, "t", t_start + dur, "steps", tot[3] + acc[0], "widest", tot[4])
            lam += nu * tau
            dur += tau
            for i in range(m):
                win.w[i] = 0.0
            if code == 0:
                break
            if code == 7:
                refresh = True
            else:
                starts[0] = win.blk[j] if code == 1 else top
                ns = 1
            if nsub >= k or t_start + dur >= t_stop:      # stop inside the stretch: keep its state
                ctx[0] = 1.0
                ctx[1], ctx[2], ctx[3], ctx[4] = base, lam, dur, t_start
                ctx[5], ctx[6], ctx[7], ctx[8] = m, cnt, h, nab
                ctx[9], ctx[10], ctx[11] = 1.0 if sub_open else 0.0, sub_t0, sub_pot
                ctx[12], ctx[13], ctx[14], ctx[15] = sub_nbl, sub_hyp, ns, 1.0 if refresh else 0.0
                g.cnt[0] = cnt
                stamp[n] = sub_id
                tot[3] += acc[0]
                return nsub, COMPLETE
        g.cnt[0] = cnt
        stamp[n] = sub_id
        tot[3] += acc[0]
        if code == 3 or code == 5:
            return nsub, code
        tot[0] += 1.0
        _event_close(m, win, g, scal, base, lam, t_start + dur, h)
    return nsub, COMPLETE


class SubeventRun:
    """One chain run whose catalog is split in time by V_th (``run_subevents``); the chain as
    ``CompiledChain`` (double precision, Taylor or DOP853 steps throughout). ``run`` goes on where the last
    call stopped, also inside an all-stuck stretch."""

    def __init__(self, law, n, ell, nu, nu_f, ends, u0, *, v_threshold: float, sigma: float = 0.0,
                 tol: float | None = None, max_steps: int = 10**15) -> None:
        from ...errors import InputError

        if isinstance(v_threshold, bool) or not isinstance(v_threshold, (int, float)) or not (
                math.isfinite(v_threshold) and v_threshold > 0):
            raise InputError("v_threshold", v_threshold, "must be finite and > 0", "give a slip velocity such as 0.1")
        kw = {} if tol is None else {"tol": tol}
        # no t_max: an all-stuck stretch may last the whole run (the bound is the number of events)
        self.chain = CompiledChain(law, n, ell, nu, nu_f, ends, u0, sigma=sigma, t_max=math.inf, max_steps=max_steps,
                                   lone=False, **kw)
        self.v_threshold = float(v_threshold)
        self._above = np.zeros(n, dtype=np.int64)
        self._stamp = np.zeros(n + 1, dtype=np.int64)
        #: [all-stuck stretches ended, slip below V_th, slip in events, DOP853 steps, widest window]
        self.totals = np.zeros(5)
        self._ctx = np.zeros(16)     # the state inside an all-stuck stretch between calls
        self._xbuf = np.zeros((4 * n + 64, 4))     # a segment's V_th crossings (``_compiled._xings``)
        self._pending = {q: np.zeros(0, dtype=np.int64 if q in ("hypocentre", "n_blocks") else np.float64)
                         for q in ("t_start", "potency", "duration", "hypocentre", "n_blocks")}

    @property
    def t(self) -> float:
        """The run's time: where the last call stopped (inside an all-stuck stretch too)."""
        return float(self._ctx[4] + self._ctx[3]) if self._ctx[0] else self.chain.t

    def run(self, k: int, t_stop: float = math.inf, every: int = 0) -> dict:
        """The next k events (or those before the time t_stop): dict(catalog, status, message)."""
        from .result import ChainStatus

        c = self.chain
        keys = ("t_start", "potency", "duration", "hypocentre", "n_blocks")
        have = self._pending["potency"].size
        code = 1
        if have < k:
            out_f = np.zeros((3, k - have + self._xbuf.shape[0]))
            out_i = np.zeros((2, out_f.shape[1]), dtype=np.int64)
            done, code = run_subevents(k - have, c._win, c._g, c._law, c._gfun, c._fr, c._par, c._scal,
                                       self.v_threshold / c.nu, self._above, self._stamp, out_f, out_i, self.totals,
                                       float(t_stop), int(every), self._ctx, self._xbuf)
            new = dict(zip(keys, (out_f[0, :done], out_f[1, :done], out_f[2, :done], out_i[0, :done], out_i[1, :done])))
            self._pending = {q: np.concatenate((self._pending[q], new[q])) for q in keys}
        # one segment can close several events: the surplus over k waits for the next call
        cat = {q: self._pending[q][:k].copy() for q in keys}
        self._pending = {q: self._pending[q][k:] for q in keys}
        status, message = ChainStatus.COMPLETE, ""
        if code == NO_STOP:
            status, message = ChainStatus.NO_STOP, f"the step size underflowed after {cat['potency'].size} events"
        elif code == NONFINITE:
            status, message = ChainStatus.NONFINITE, f"non-finite state after {cat['potency'].size} events"
        return dict(catalog=cat, status=status, message=message)


