"""The event loop of a chain run: quiescent jumps, windows of slipping blocks, exact events.

Algorithm (docs/chain.md, "Event algorithm"):

1. All blocks stuck: the stress grows as νt, so the next failure is the block with the largest σ,
   at t + (1 − max σ)/ν. Jump there (σ_j += 1 − max σ, the failing block set to σ = 1 exactly).
2. Integrate a *window* of M consecutive blocks (M a power of two, or the whole chain) that holds
   every block that slipped in this event, stuck blocks inside it included, with the compiled window
   integrator (``_integrator``) in per-segment scaled variables. The two outside neighbours have start
   events; every other block is far: stuck, with σ growing as ντ, so its failure time −d_j/ν is known
   in closed form and bounds the segment.
3. A stop (x_j → 0) sticks a block, a switch flips its friction piece; both continue the segment.
   A start (of a stuck window block, an outside neighbour, or a far block at its bound) *commits*
   the segment to the global state (σ, U updated exactly from the scaled increments) and starts a new
   segment from w = 0 with the starting block at σ = 1 exactly, in a larger window if it is outside.
4. When no block slips, the event ends; the catalog records it.

The global state is the stress σ_j itself (never recomputed from U and νt, which grow without
bound), the displacements U_j and the time t.
"""

from __future__ import annotations

import math

import heyoka as hy
import numpy as np

from ...laws import FrictionLaw
from ._integrator import N_GLOBAL, window_integrator
from .result import ChainStatus

__all__ = ["ChainLoop"]

_NONFINITE = hy.taylor_outcome.err_nf_state


def _pow2_at_least(k: int) -> int:
    return 1 << max(k - 1, 0).bit_length()


class ChainLoop:
    """One chain run: global state and the per-event loop (use ``run(k)``)."""

    def __init__(self, law: FrictionLaw, n: int, ell: float, nu: float, nu_f: float, ends: str,
                 u0: np.ndarray, *, precision: str = "double", energy: bool = False,
                 t_max: float = 1e5, max_steps: int = 1_000_000, full_window: bool = False) -> None:
        from ...engine._integrator import fp_info

        _, dtype, _ = fp_info(precision)
        self.dtype = dtype
        self.law, self.n, self.ends, self.precision, self.energy = law, n, ends, precision, energy
        self.nu, self.nu_f, self.l2 = dtype(nu), dtype(nu_f), dtype(ell) * dtype(ell)
        self.periodic = ends == "periodic"
        self.t_max, self.max_steps = t_max, max_steps
        self.u = np.array([dtype(float(x)) for x in u0], dtype=dtype) if dtype is not np.float64 \
            else np.array(u0, dtype=np.float64)
        self.sigma = self._laplacian(self.u) * self.l2 - self.u       # σ_j(0), νt = 0
        self.t = dtype(0)
        self.vel = np.zeros(n, dtype=dtype)        # scaled velocities v = V/ν
        self.slipping = np.zeros(n, dtype=bool)
        self.piece = np.zeros(n, dtype=np.int64)
        if energy:
            self.y = -self.u.copy()                # stretch of the pulling springs νt − U_j
            self.bond = self._bonds(self.u)
        # the largest window that is still "partial" (its outside neighbours distinct)
        self.partial_max = n - 2 if self.periodic else n - 1
        #: how often each way of starting a block happened (tests check that every path is exercised)
        self.counts = {"window": 0, "grow": 0, "far": 0, "overloaded": 0}
        if full_window:   # integrate the whole chain every event (the tests' check of the windows)
            self.partial_max = 0

    # -- chain geometry ---------------------------------------------------------------------------
    def _laplacian(self, a: np.ndarray) -> np.ndarray:
        if self.periodic:
            return np.roll(a, 1) - 2 * a + np.roll(a, -1)
        left = np.concatenate((a[:1], a[:-1]))
        right = np.concatenate((a[1:], a[-1:]))
        return left - 2 * a + right

    def _bonds(self, a: np.ndarray) -> np.ndarray:
        return np.roll(a, -1) - a if self.periodic else np.diff(a)

    def _place(self, lo: int, hi: int, at_least: int) -> tuple[int, int]:
        """(start, size) of a window covering the unwrapped block range [lo, hi]."""
        span = hi - lo + 1
        m = _pow2_at_least(max(span, at_least))
        if m > self.partial_max or span > self.partial_max:
            return 0, self.n
        a = lo - (m - span) // 2
        if not self.periodic:
            a = min(max(a, 0), self.n - m)
        return a, m

    # -- the run ------------------------------------------------------------------------------------
    def run(self, k: int) -> dict:
        cat = {f: [] for f in ("t_start", "hypocentre", "n_blocks", "potency", "duration",
                                "max_velocity", "steps", "driver_work", "dissipation", "elastic_change")}
        status, message = ChainStatus.COMPLETE, ""
        for _ in range(k):
            ok, message = self._event(cat)
            if not ok:
                status = ChainStatus.NONFINITE if message.startswith("non-finite") else ChainStatus.NO_STOP
                break
        return dict(catalog=cat, status=status, message=message)

    def _event(self, cat: dict) -> tuple[bool, str]:
        dtype = self.dtype
        h = int(np.argmax(self.sigma))
        jump = 1 - self.sigma[h]
        self.sigma += jump
        self.sigma[h] = 1
        self.t += jump / self.nu
        if self.energy:   # the quiescent phase stretches the pulling springs; no energy is dissipated
            self.y += jump
        t_start = self.t
        self.slipping[h], self.vel[h], self.piece[h] = True, 0, 0
        touched = [h]
        self._touched = {h}
        self.ev = dict(potency=dtype(0), duration=dtype(0), vmax=dtype(0), steps=0,
                       work=dtype(0), diss=dtype(0), elastic=dtype(0))
        a, m = self._place(h, h, 1)
        ok, message = self._segments(a, m)
        ev = self.ev
        cat["t_start"].append(t_start)
        cat["hypocentre"].append(h)
        cat["n_blocks"].append(len(self._touched))
        cat["potency"].append(ev["potency"])
        cat["duration"].append(ev["duration"])
        cat["max_velocity"].append(self.nu * ev["vmax"])
        cat["steps"].append(ev["steps"])
        if self.energy:
            cat["driver_work"].append(ev["work"])
            cat["dissipation"].append(ev["diss"])
            cat["elastic_change"].append(ev["elastic"])
        del touched
        if not ok:
            for f in cat:   # an unfinished event is not catalogued
                if cat[f]:
                    cat[f].pop()
        return ok, message

    def _indices(self, a: int, m: int) -> np.ndarray:
        return np.arange(a, a + m) % self.n

    def _segments(self, a: int, m: int) -> tuple[bool, str]:
        """Integrate the event from its first failure until every block is stuck."""
        n, nu = self.n, self.nu
        while True:
            idx = self._indices(a, m)
            full = m == self.n
            if full:
                left = right = -1
            else:
                left = -1 if (not self.periodic and a == 0) else (a - 1) % n
                right = -1 if (not self.periodic and a + m == n) else (a + m) % n
            # blocks already at the threshold start now (simultaneous failures)
            for j in idx:
                if not self.slipping[j] and self.sigma[j] >= 1:
                    self._start(j)
            grow = [k for k in (left, right) if k >= 0 and self.sigma[k] >= 1]
            if grow:
                a, m = self._grow(a, m, grow[0])
                continue
            wi = window_integrator(self.law, m, self.precision, self.energy)
            outcome = self._integrate(wi, idx, a, m, left, right, full)
            if outcome is None:
                return True, ""
            if isinstance(outcome, str):
                return False, outcome
            kind, k = outcome
            self.counts[kind] += 1
            if kind == "window":
                self._start(k)
            else:
                self._start(k)
                a, m = self._grow(a, m, k)

    def _start(self, j: int) -> None:
        self.sigma[j] = 1   # the start event located σ_j = 1; rounding of the commit is dropped
        self.slipping[j], self.vel[j], self.piece[j] = True, 0, 0
        self._touched.add(int(j))

    def _grow(self, a: int, m: int, k: int) -> tuple[int, int]:
        lo, hi = a, a + m - 1
        if self.periodic:   # unwrap k next to the window, the shorter way round
            k = min((k + s for s in (-self.n, 0, self.n)), key=lambda kk: max(lo, kk) - min(hi, kk))
        return self._place(min(lo, k), max(hi, k), 2 * m)

    def _integrate(self, wi, idx, a, m, left, right, full):
        """One or more segments in this window; returns None (event over), an error string, or the
        block that starts: ("window", j) inside, ("grow", j) outside."""
        dtype, nu = self.dtype, self.nu
        ta = wi.integrator
        pars, state = ta.pars, ta.state
        pars[0], pars[1], pars[2] = nu, self.nu_f, self.l2
        periodic = self.periodic
        pars[3] = 1 if (full and periodic) else 0
        pars[4] = 1 if (not periodic and a == 0) else 0
        pars[5] = 1 if (not periodic and a + m == self.n) else 0
        for side, nb in ((0, left), (1, right)):
            if nb >= 0:
                d = self.sigma[nb] - 1
                pars[6 + side], pars[8 + side] = 1, d
                pars[10 + side] = 1 / max(dtype(1), abs(d) / nu)
            else:
                pars[6 + side], pars[8 + side], pars[10 + side] = 0, 0, 1
        d = self.sigma[idx] - 1
        slip = self.slipping[idx]
        pars[N_GLOBAL:N_GLOBAL + m] = slip
        pars[N_GLOBAL + m:N_GLOBAL + 2 * m] = d
        q = np.abs(d) / nu
        q[q < 1] = 1
        pars[N_GLOBAL + 2 * m:N_GLOBAL + 3 * m] = 1 / q
        k_pieces = wi.n_pieces
        pieces = self.piece[idx]
        if k_pieces > 1:
            base = N_GLOBAL + 3 * m
            pars[base:base + k_pieces * m] = 0
            pars[base + pieces * m + np.arange(m)] = 1
        state[:] = 0
        state[m:2 * m] = self.vel[idx]
        ta.time = dtype(0)
        ta.reset_cooldowns()
        rec = wi.recorder
        rec.vmax = self.ev["vmax"]
        # far blocks: stuck, σ grows as ντ: the first of them fails at τ = (1 − σ)/ν
        if full:
            tau_far, far = math.inf, -1
        else:
            masked = self.sigma.copy()
            masked[idx] = -np.inf
            for nb in (left, right):
                if nb >= 0:
                    masked[nb] = -np.inf
            far = int(np.argmax(masked))
            tau_far = (1 - masked[far]) / nu if masked[far] > -np.inf else math.inf
        t_left = dtype(self.t_max) - self.ev["duration"]
        t_end = min(tau_far, t_left)
        kinds, blocks, breaks = wi.event_kind, wi.event_block, wi.event_break
        n_events = len(kinds)
        slipping = int(slip.sum())
        p0 = N_GLOBAL
        steps = self.ev["steps"]
        while True:
            outcome, _, _, nsteps, *_ = ta.propagate_until(t_end, max_steps=max(self.max_steps - steps, 1))
            steps += nsteps
            index = -int(outcome) - 1
            if not 0 <= index < n_events:
                self.ev["steps"] = steps
                if outcome == _NONFINITE:
                    return f"non-finite state at t = {float(self.t + ta.time):.17g}"
                if ta.time >= t_end and tau_far <= t_left:
                    self._commit(wi, idx, m, pieces)
                    self.counts["far"] += 1
                    return ("grow", far)
                return (f"event at t = {float(self.t):.17g} did not end before t_max = {self.t_max:g} "
                        f"or max_steps = {self.max_steps} (steps = {steps})")
            kind = kinds[index]
            j = blocks[index]
            if kind == "block":
                if pars[p0 + j]:                 # a stop
                    if self._overloaded(ta, wi, j, m, a):
                        state[m + j] = 0         # σ ≥ 1 at V = 0: it keeps slipping
                        self.counts["overloaded"] += 1
                        continue
                    pars[p0 + j] = 0
                    state[m + j] = 0
                    slipping -= 1
                    if slipping == 0:
                        self.ev["steps"] = steps
                        self._commit(wi, idx, m, pieces)
                        return None
                else:                            # a stuck block of the window starts
                    self.ev["steps"] = steps
                    self._commit(wi, idx, m, pieces)
                    return ("window", int(idx[j]))
            elif kind == "switch":
                b = breaks[index]
                pc = pieces[j]
                base = N_GLOBAL + 3 * m
                pars[base + pc * m + j] = 0
                pc = pc + 1 if b == pc else pc - 1
                pars[base + pc * m + j] = 1
                pieces[j] = pc
            else:                                # an outside neighbour starts
                self.ev["steps"] = steps
                self._commit(wi, idx, m, pieces)
                return ("grow", left if kind == "left" else right)

    def _overloaded(self, ta, wi, j, m, a) -> bool:
        """σ_j ≥ 1 at a stop (only at rounding level): the block cannot stick."""
        pars, w = ta.pars, ta.state
        l2 = pars[2]
        lft = w[j - 1] if j > 0 else pars[3] * w[m - 1] + pars[4] * w[0]
        rgt = w[j + 1] if j < m - 1 else pars[3] * w[0] + pars[5] * w[m - 1]
        load = pars[N_GLOBAL + m + j] / pars[0] + l2 * (lft - 2 * w[j] + rgt) - w[j] + ta.time
        return load >= 0

    def _commit(self, wi, idx, m, pieces) -> None:
        """Fold the segment's scaled increments into the global state (exact up to rounding)."""
        ta = wi.integrator
        nu, tau = self.nu, ta.time
        state, pars = ta.state, ta.pars
        dw = np.zeros(self.n, dtype=self.dtype)
        dw[idx] = state[:m]
        self.vel[idx] = state[m:2 * m]
        self.slipping[idx] = pars[N_GLOBAL:N_GLOBAL + m] != 0
        self.piece[idx] = pieces
        if self.energy:
            dy = nu * (tau - dw)
            db = nu * self._bonds(dw)
            self.ev["elastic"] += np.sum(self.y * dy + dy * dy / 2) + \
                self.l2 * np.sum(self.bond * db + db * db / 2)
            self.ev["work"] += nu * (np.sum(self.y) * tau + nu * self.n * tau * tau / 2 - nu * state[2 * m + 1])
            self.ev["diss"] += nu * state[2 * m]
            self.y += dy
            self.bond += db
        self.sigma += nu * (self.l2 * self._laplacian(dw) - dw + tau)
        self.u[idx] += nu * state[:m]
        self.ev["potency"] += nu * np.sum(state[:m])
        self.ev["duration"] += tau
        self.ev["vmax"] = max(self.ev["vmax"], wi.recorder.vmax)
        self.t += tau
