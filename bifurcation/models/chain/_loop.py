"""The event loop of a chain run: quiescent jumps, windows of slipping blocks, exact events.

Algorithm (docs/chain.md, "Event algorithm"):

1. All blocks stuck: the stress grows as νt, so the next failure is the block with the largest σ,
   at t + (1 − max σ)/ν. Jump there (σ_j += 1 − max σ, the failing block set to σ = 1 exactly).
2. Integrate a *window*: the set S of blocks slipping now and their chain neighbours (stuck ones
   included), packed into M positions (M a power of two ≥ |S|, or |S| for the whole
   chain) of the compiled window integrator (``_integrator``), in per-segment scaled variables.
   Every block outside S is stuck and none of its neighbours moves, so its stress grows as ντ and
   its failure time −d_j/ν is known in closed form: the first of them bounds the segment.
3. A stop (x_j → 0) sticks a block, a switch flips its friction piece; both continue the segment.
   A start (of a stuck block of S, or of a block outside S at its bound) *commits* the segment to
   the global state (σ, U updated exactly from the scaled increments), adds the block and its
   neighbours to S and starts a new segment from w = 0 with the starting block at σ = 1 exactly;
   blocks that stopped since the last start leave S then. Several clusters far apart share one
   window, so the cost follows the blocks slipping at the same time, not N nor the event's size.
4. When no block slips, the event ends; the catalog records it.

The global state is the stress σ_j itself (never recomputed from U and νt, which grow without
bound), the displacements U_j and the time t.
"""

from __future__ import annotations

import math
import time

import heyoka as hy
import mpmath
import numpy as np

from ...laws import FrictionLaw
from ._integrator import COMPACT_ABOVE, ENERGY_SCALE, window_integrator
from .result import ChainStatus

__all__ = ["ChainLoop"]

_NONFINITE = hy.taylor_outcome.err_nf_state
_TIME_LIMIT = hy.taylor_outcome.time_limit


#: The layout cache's bounds: windows, and blocks over all of them (212 bytes a block, measured: ≤ 56 MB)
_LAYOUT_WINDOWS, _LAYOUT_BLOCKS = 8192, 1 << 18


def _pow2_at_least(k: int) -> int:
    return 1 << max(k - 1, 0).bit_length()


class _Segment:
    """One segment of an event in one window: what its event handlers (``ChainLoop._stops``,
    ``_side``, ``_switches``, ``_commit``) share. ``p`` and ``pieces`` change as blocks stop and
    switch; ``stopped`` collects the blocks that stopped (they leave S at the commit)."""

    __slots__ = ("wi", "ta", "idx", "at", "k", "m", "sg", "d", "p", "pieces", "bond", "selfc",
                 "nu", "l2", "nu_f", "stopped", "velocities")

    def __init__(self, wi, idx, at, sg, d, p, pieces, bond, selfc, nu, l2, nu_f) -> None:
        self.wi, self.ta, self.idx, self.at, self.k, self.m = wi, wi.integrator, idx, at, len(idx), wi.m
        self.sg, self.d, self.p, self.pieces, self.bond, self.selfc = sg, d, p, pieces, bond, selfc
        self.nu, self.l2, self.nu_f = nu, l2, nu_f
        self.stopped = []
        self.velocities = wi.layout.velocities(len(idx))   # the state slots of the blocks' v

    def load(self, j: int):
        """(σ_j − 1)/ν of position j now (scaled variables, the integrator's own expression)."""
        # w_i is state slot i (``WindowState``); the left neighbour of position 0 is w[m − 1], not state[−1]
        w, m, bond = self.wi.state, self.m, self.bond
        coupling = bond[j - 1] * w[(j - 1) % m] + bond[j] * w[(j + 1) % m] + (self.selfc[j] - 2) * w[j]
        return self.d[j] / self.nu + self.l2 * coupling - w[j] + self.ta.time

    def switch(self, i: int, pc: int) -> None:
        """Move position i to piece ``pc`` (its one-hot selector)."""
        wi, pieces = self.wi, self.pieces
        wi.pars[wi.params.selector(pieces[i], i)] = 0
        wi.pars[wi.params.selector(pc, i)] = 1
        pieces[i] = pc


class ChainLoop:
    """One chain run: global state and the per-event loop (use ``run(k)``)."""

    def __init__(self, law: FrictionLaw, n: int, ell: float, nu: float, nu_f: float, ends: str,
                 u0: np.ndarray, *, precision: str = "double", energy: bool = False,
                 t_max: float = 1e5, max_steps: int = 1_000_000, full_window: bool = False,
                 compact_above: int = COMPACT_ABOVE, timing: bool = False, drop: float = 0.0,
                 v_threshold: float = 0.0, exact: dict | None = None, max_work: int | None = None,
                 max_run_work: int | None = None) -> None:
        from ...engine._exact import at_precision
        from ...engine._integrator import fp_info

        _, dtype, _ = fp_info(precision)
        self.dtype = dtype
        self.law, self.n, self.ends, self.precision, self.energy = law, n, ends, precision, energy
        # ``exact``: the inputs as given (decimal text), read at the run's precision (engine._exact)
        given = {"nu": nu, "nu_f": nu_f, "ell": ell, "u0": u0, "sigma": drop, **(exact or {})}
        ell_p = at_precision(given["ell"], dtype)
        self.nu, self.nu_f, self.l2 = at_precision(given["nu"], dtype), at_precision(given["nu_f"], dtype), ell_p * ell_p
        self.periodic = ends == "periodic"
        self.t_max, self.max_steps = t_max, max_steps
        #: a bound on one event's block-steps (Σ Taylor steps × window width, the cost of its steps), or
        #: None: the CLI's bound on a run whose event may never end (N·ν ≥ 1 at large N; cli/_chain.py)
        self.max_work = max_work
        #: the same bound on all the events of this loop together (the CLI's bound on a run), or None
        self.max_run_work, self.run_work = max_run_work, 0
        #: the friction drop σ (docs/chain.md, "Friction drop"): Φ_σ(x) = (1 − σ)Φ(x/(1 − σ)). σ = 0 takes
        #: the unmodified integrator and code path (bit-identical catalogs); σ > 0 its own integrator
        self.drop = float(drop)
        self._drop_on = self.drop > 0
        self._drop_pars = ()
        #: event membership (docs/chain.md, "Event membership"): 0 counts every block that moved (the
        #: event runs until all are stuck); V_th > 0 counts, in n_blocks and potency, only the blocks
        #: whose velocity exceeded V_th during the event (the dynamics is the same either way)
        self.v_threshold = float(v_threshold)
        self._vth = self.v_threshold / float(nu) if self.v_threshold > 0 else None   # in v = V/ν
        if self._drop_on:
            drop_p = at_precision(given["sigma"], dtype)
            self._drop_pars = (drop_p, dtype(1) - drop_p)
        self.u = np.array([at_precision(x, dtype) for x in given["u0"]], dtype=dtype) if dtype is not np.float64 \
            else np.array(u0, dtype=np.float64)
        self.sigma = self._laplacian(self.u) * self.l2 - self.u       # σ_j(0), νt = 0
        self.t = dtype(0)
        self.vel = np.zeros(n, dtype=dtype)        # scaled velocities v = V/ν
        self.slipping = np.zeros(n, dtype=bool)
        self.piece = np.zeros(n, dtype=np.int64)
        if energy:
            self.y = -self.u.copy()                # stretch of the pulling springs νt − U_j
            self.bond = self._bonds(self.u)
        #: integrate the whole chain every event (the tests' check of the windows)
        self.force_full = full_window
        #: windows up to this size use heyoka's full mode (faster steps, long first compile)
        self.compact_above = compact_above
        self.wall: list[float] = []   # seconds per event (benchmarks: cost against event size)
        #: CPU seconds of this process per event, with ``timing`` only: a CPU clock is a system call
        #: that costs ~150 µs in some sandboxes (measured here: 8 % of a run at N = 256)
        self.cpu: list[float] = []
        self.timing = timing
        self.widest: list[int] = []   # per event, the most blocks one window held
        #: how often each way of starting a block happened (tests check that every path is exercised)
        self.counts = {"window": 0, "grow": 0, "far": 0, "overloaded": 0}
        #: per block: itself and its chain neighbours (the window a slipping block needs)
        self._near = [(j, *self._neighbours(j)) for j in range(n)]
        self._slip: set = set()      # the blocks slipping now (during an event)
        self._windows: dict = {}     # per window size M: its compiled integrator
        #: per piece of the law: the x interval [lower, upper) where it holds
        self._bounds = ([pc.lower for pc in law.pieces], [pc.lower for pc in law.pieces[1:]] + [math.inf])
        #: per breakpoint b: g = 1 − Φ there (the law is continuous: both pieces agree), for the side a
        #: block crosses to (``_side``)
        self._g_break = [dtype(float(law.pieces[i + 1].drop_mp(mpmath.mpf(b))))
                         for i, b in enumerate(law.breakpoints)]
        if self._drop_on:   # g_σ at the breakpoint x = (1 − σ) b: σ + (1 − σ) g(b)
            with mpmath.workdps(40):
                s_mp = mpmath.mpf(self.drop)
                self._g_break = [dtype(float(s_mp + (1 - s_mp) * law.pieces[i + 1].drop_mp(mpmath.mpf(b))))
                                 for i, b in enumerate(law.breakpoints)]
        self._layouts: dict = {}     # per window (its blocks, sorted): ``_window_layout``
        self._layout_blocks = 0      # the blocks the cached layouts hold
        # the segment's slip, summed exactly rounded in double (math.fsum) and in the dtype otherwise
        self._sum = math.fsum if dtype is np.float64 else sum
        # the hot path's scalars: Python floats in double (numpy scalars cost several times more per
        # operation and round the same), the dtype's own scalars otherwise (real128 in quad)
        self._scalar = float if dtype is np.float64 else (lambda x: x)
        self._zero, self._one, self._pad = (self._scalar(dtype(x)) for x in (0, 1, -1e3))
        #: (σ, 1 − σ), the values of the drop integrator's slots "sigma" and "c" (empty at σ = 0)
        self._drop_pars = tuple(self._scalar(x) for x in self._drop_pars)
        self._drop_c = self._drop_pars[-1] if self._drop_on else None

    # -- chain geometry ---------------------------------------------------------------------------
    def _laplacian(self, a: np.ndarray) -> np.ndarray:
        if self.periodic:
            return np.roll(a, 1) - 2 * a + np.roll(a, -1)
        left = np.concatenate((a[:1], a[:-1]))
        right = np.concatenate((a[1:], a[-1:]))
        return left - 2 * a + right

    def _bonds(self, a: np.ndarray) -> np.ndarray:
        return np.roll(a, -1) - a if self.periodic else np.diff(a)

    def _neighbours(self, j: int) -> tuple[int, ...]:
        n = self.n
        if self.periodic:
            return tuple({(j - 1) % n, (j + 1) % n} - {j})
        return tuple(k for k in (j - 1, j + 1) if 0 <= k < n)

    def _members(self) -> list:
        """The window: the slipping blocks and their chain neighbours, sorted (all blocks if forced).

        A block outside it is stuck and so are its neighbours (a neighbour in the window that does not
        slip stays at w = 0 until it starts, which ends the segment), so its stress grows as ντ."""
        if self.force_full:
            return list(range(self.n))
        near = self._near
        window = set()
        for j in self._slip:
            window.update(near[j])
        return sorted(window)

    def _layout(self) -> tuple[list, np.ndarray, frozenset, int, list, list]:
        """The window of the blocks slipping now: ``_window_layout(_members())`` and the window's
        blocks as an index array and a set, cached by the set of slipping blocks (windows recur: a
        pulse crossing the chain passes the same stretches again and again; the cache is bounded)."""
        key = frozenset(self._slip)
        hit = self._layouts.get(key)
        if hit is None:
            idx, m, bond, selfc = self._window_layout(self._members())
            # bounded in blocks, not only in windows: 8192 windows of thousands of blocks each (an event that
            # widens without end at large N, N·ν ~ 1) held 212 bytes a block (measured), gigabytes in all
            if len(self._layouts) >= _LAYOUT_WINDOWS or self._layout_blocks + len(idx) > _LAYOUT_BLOCKS:
                self._layouts.clear()
                self._layout_blocks = 0
            hit = self._layouts[key] = (idx, np.array(idx, dtype=np.intp), frozenset(idx), m, bond, selfc)
            self._layout_blocks += len(idx)
        return hit

    def _window_layout(self, idx: list) -> tuple[list, int, list, list]:
        """Window positions of the blocks ``idx`` (sorted): (chain index per position, M, bonds, self
        couplings). Position i is bonded to i + 1 where the two blocks are chain neighbours.

        Python lists, not arrays: a window holds a few blocks, and the segment's hot path reads them
        element by element (``_layout`` computes this on a cache miss only)."""
        n, k = self.n, len(idx)
        if self.periodic and k < n:   # start the cyclic order after a gap: no bond wraps the order
            gap = next((i for i, j in enumerate(idx) if j != i), k)
            idx = idx[gap:] + idx[:gap]
        m = n if k == n else _pow2_at_least(k)
        right = [(j + 1) % n for j in idx] if self.periodic else [j + 1 for j in idx]
        bond = [0.0] * m
        for i in range(k - 1):
            bond[i] = float(right[i] == idx[i + 1])
        if k == m:
            bond[k - 1] = float(right[-1] == idx[0])
        selfc = [0.0] * m
        if not self.periodic:
            for i, j in enumerate(idx):
                selfc[i] = float(j == 0) + float(j == n - 1)
        return idx, m, bond, selfc

    # -- the run ------------------------------------------------------------------------------------
    def run(self, k: int) -> dict:
        cat = {f: [] for f in ("t_start", "hypocentre", "n_blocks", "potency", "duration",
                                "max_velocity", "steps", "driver_work", "dissipation", "elastic_change",
                                "n_blocks_all", "potency_all")}
        status, message = ChainStatus.COMPLETE, ""
        # the blocks the run touches keep their displacement and piece in dicts (read and written per
        # segment); the arrays are written once, when the run returns
        self._u, self._pc = {}, {}
        try:
            for _ in range(k):
                ok, message = self._event(cat)
                if not ok:
                    status = (ChainStatus.NONFINITE if message.startswith("non-finite") else
                              ChainStatus.BACK_SLIP if message.startswith("back-slip") else ChainStatus.NO_STOP)
                    break
        finally:
            self._flush()
        return dict(catalog=cat, status=status, message=message)

    def _event(self, cat: dict) -> tuple[bool, str]:
        started, cpu = time.perf_counter(), time.process_time() if self.timing else 0.0
        dtype = self.dtype
        h = int(np.argmax(self.sigma))
        top = self.sigma[h].copy()
        jump = 1 - top
        # σ_j − max σ + 1, not σ_j + (1 − max σ): a block tied with the hypocentre reaches 1 exactly
        # (0 + 1). The other form rounds to 1 − 2⁻⁵³ for about one max σ < 0.5 in eight, and the tied
        # block then starts ulp/ν later (1e-4 at ν = 1e-12: its event lasted 1e-5 too long)
        self.sigma -= top
        self.sigma += 1
        self.sigma[h] = 1
        self.t += jump / self.nu
        if self.energy:   # the quiescent phase stretches the pulling springs; no energy is dissipated
            self.y += jump
        t_start = self.t
        # the slipping blocks' velocities (all zero between events: never in the arrays but after an
        # unfinished event)
        self._v = {}
        self._touched, self._slip = set(), set()
        if self._vth is not None:
            # per touched block: its largest v and its slip, summed from the segments' increments (U
            # itself grows without bound, so U(end) − U(start) would cancel digits)
            self._vblock, self._sblock = {}, {}
        self._start(h)
        self._widest = 0
        self._due = None     # after the quiescent jump: scan every block for simultaneous failures
        self._hot = self._scalars()
        self.ev = dict(potency=dtype(0), duration=dtype(0), vmax=dtype(0), steps=0,
                       work=dtype(0), diss=dtype(0), elastic=dtype(0), block_steps=0)
        ok, message = self._segments()
        ev = self.ev
        cat["t_start"].append(t_start)
        cat["hypocentre"].append(h)
        if self._vth is None:
            cat["n_blocks"].append(len(self._touched))
            cat["potency"].append(ev["potency"])
        else:
            # only the blocks that exceeded V_th: their own slips, summed exactly rounded
            members = [j for j in self._touched if self._vblock[j] > self._vth]
            cat["n_blocks"].append(len(members))
            cat["potency"].append(self.dtype(self._sum([self._sblock[j] for j in members])))
            cat["n_blocks_all"].append(len(self._touched))
            cat["potency_all"].append(ev["potency"])
        cat["duration"].append(ev["duration"])
        cat["max_velocity"].append(self.nu * ev["vmax"])
        cat["steps"].append(ev["steps"])
        self.wall.append(time.perf_counter() - started)
        if self.timing:
            self.cpu.append(time.process_time() - cpu)
        self.widest.append(self._widest)
        if self.energy:
            cat["driver_work"].append(ev["work"])
            cat["dissipation"].append(ev["diss"])
            cat["elastic_change"].append(ev["elastic"])
        if not ok:
            for f in cat:   # an unfinished event is not catalogued
                if cat[f]:
                    cat[f].pop()
        return ok, message

    def _flush(self) -> None:
        """Write the run's per-block dicts into the state arrays (after an event every block is
        stuck: V = 0 exactly; an unfinished one leaves its slipping blocks marked as such)."""
        if self._u:
            self.u[list(self._u)] = list(self._u.values())
        if self._pc:
            self.piece[list(self._pc)] = list(self._pc.values())
        self._u, self._pc = {}, {}
        if self._slip:
            slip = sorted(self._slip)
            self.slipping[slip] = True
            self.vel[slip] = [self._v.get(j, 0) for j in slip]

    def _segments(self) -> tuple[bool, str]:
        """Integrate the event from its first failure until every block is stuck."""
        while True:
            # a new segment's window: the blocks slipping now and their neighbours (blocks that slipped
            # earlier in the event and stopped leave it: a slip pulse keeps a window of its own width)
            # blocks at the threshold start now (simultaneous failures; anywhere in the chain: a block
            # outside the window at σ ≥ 1 would otherwise give a far bound τ ≤ 0)
            due = self._due
            for j in (np.flatnonzero(self.sigma >= 1).tolist() if due is None else due):
                if j not in self._slip:
                    self._start(j)
            idx, at, members, m, bond, selfc = self._layout()
            self._widest = max(self._widest, len(idx))
            wi = self._windows.get(m)
            if wi is None:
                wi = self._windows[m] = window_integrator(self.law, m, self.precision, self.energy,
                                                          self.compact_above, self._drop_on)
            outcome = self._integrate(wi, idx, at, members, bond, selfc)
            if outcome is None:
                return True, ""
            if isinstance(outcome, str):
                return False, outcome
            kind, j = outcome
            self.counts[kind] += 1
            if kind == "window" and any(k not in members for k in self._near[j]):
                self.counts["grow"] += 1
            self._start(j)

    def _start(self, j: int) -> None:
        if self._vth is not None and j not in self._touched:
            self._sblock[j] = self._zero
            self._vblock[j] = self._zero
        self.sigma[j] = 1   # the start event located σ_j = 1; rounding of the commit is dropped
        self._v[j] = self._zero
        self._pc[j] = 0
        self._touched.add(j)
        self._slip.add(j)

    def _scalars(self) -> tuple:
        """ν, ℓ², t_max and ν_f as the hot path's scalars (read at each event: a sweep changes ν_f)."""
        f = self._scalar
        return f(self.nu), f(self.l2), f(self.dtype(self.t_max)), f(self.nu_f)

    def _integrate(self, wi, idx, at, members, bond, selfc):
        """Segments in this window until the event ends (None), an error (a string), or a block starts:
        ("window", j) of S, ("far", j) outside S.

        The window's numbers live in Python lists for the segment (scalars of the loop's dtype: floats
        in double, real128 in quad) and reach the integrator in one write of its parameters and one of
        its state; the arithmetic is the same, operation by operation, as on arrays."""
        nu, l2, t_max, nu_f = self._hot
        ta, pars, state = wi.integrator, wi.pars, wi.state
        m, k = wi.m, len(idx)
        sigma = self.sigma
        sg = sigma[at].tolist()             # σ of the window's blocks at the segment's start
        # padding positions: stuck, σ = −999 (a constant like −1e100 spoils heyoka's step control);
        # a start of one (only after τ = 1e3/ν) is ignored below
        d = [x - 1 for x in sg] + [self._pad] * (m - k)
        one = 1 / self._one
        qinv = [one if (q := abs(x) / nu) < 1 else 1 / q for x in d]
        slip, vd, pcd = self._slip, self._v, self._pc
        p = [1.0 if j in slip else 0.0 for j in idx] + [0.0] * (m - k)
        pieces = None                            # a one-piece law has no piece to track
        if wi.n_pieces > 1:
            # a stuck neighbour that has not started keeps the piece it had (never used while it is
            # stuck: its switch events cannot fire at V = 0; the start resets it)
            pieces = [pcd[j] if j in pcd else int(self.piece[j]) for j in idx] + [0] * (m - k)
        pars[:] = wi.params.pack(nu=nu, nu_f=nu_f, l2=l2, p=p, d=d, q=qinv, bond=bond, selfc=selfc,
                                 pieces=pieces, drop=self._drop_pars)
        st = [0.0] * len(state)
        st[wi.layout.velocities(k)] = [vd.get(j, 0.0) for j in idx]
        state[:] = st
        ta.time = self._zero
        ta.reset_cooldowns()
        wi.recorder.vmax = self.ev["vmax"]
        if self._vth is not None:
            vb = self._vblock
            wi.recorder.vpos = [vb.get(j, self._zero) for j in idx] + [self._zero] * (m - k)
        else:
            wi.recorder.vpos = None   # the integrator is shared (cached per process)
        # blocks outside S: stuck, σ grows as ντ: the first of them fails at τ = (1 − σ)/ν
        if k == self.n:
            tau_far, far = math.inf, -1
            self._sigma_far = None
        else:
            far = int(sigma.argmax())
            if far in members:    # the largest stress is in the window: mask it
                sigma[at] = -np.inf             # (in place, restored at once)
                far = int(sigma.argmax())
                sigma[at] = sg
            sigma_far = self._scalar(sigma[far])
            tau_far = (1 - sigma_far) / nu
            self._sigma_far = sigma_far
        t_left = t_max - self.ev["duration"]
        t_end = min(tau_far, t_left)
        kinds, blocks, breaks = wi.event_kind, wi.event_block, wi.event_break
        n_events = len(kinds)
        slipping = int(sum(p))
        steps = self.ev["steps"]
        seg = _Segment(wi, idx, at, sg, d, p, pieces, bond, selfc, nu, l2, nu_f)
        while True:
            allowed = max(self.max_steps - steps, 1)
            left = self._work_left()
            if left is not None:   # the steps this window's width leaves of the work bounds
                allowed = min(allowed, left // m)
                if allowed < 1:
                    self.ev["steps"] = steps
                    return self._over_work(steps, k)
            outcome, _, _, nsteps, *_ = ta.propagate_until(t_end, max_steps=allowed)
            steps += nsteps
            self.ev["block_steps"] += nsteps * m
            self.run_work += nsteps * m
            index = -int(outcome) - 1
            if not 0 <= index < n_events:
                self.ev["steps"] = steps
                if outcome == _NONFINITE:
                    return f"non-finite state at t = {float(self.t + ta.time):.17g}"
                # reached t_end: the far bound if it came first. By the outcome, not by ta.time >= t_end:
                # heyoka keeps time in double-length and ta.time can read one ulp below t_end (a far start
                # was reported as no-stop after 74 steps; tests/test_chain_adversarial.py)
                if outcome == _TIME_LIMIT and tau_far <= t_left:
                    self._commit(seg)
                    return self._back_slip(idx) or ("far", far)
                if left is not None and left // m <= nsteps:
                    return self._over_work(steps, k)
                return (f"event at t = {float(self.t):.17g} did not end before t_max = {self.t_max:g} "
                        f"or max_steps = {self.max_steps} (steps = {steps})")
            j = blocks[index]
            if j >= k or kinds[index] == "rung":     # a rung only ends a step (``_integrator``)
                continue
            if kinds[index] == "block":
                if p[j]:                         # a stop (and any stop at the same instant)
                    slipping -= self._stops(seg, j)
                    if slipping == 0:
                        self.ev["steps"] = steps
                        self._commit(seg)
                        return self._back_slip(idx)
                else:                            # a stuck block of S starts
                    self.ev["steps"] = steps
                    self._commit(seg)
                    return self._back_slip(idx) or ("window", idx[j])
            else:                                # a switch of the friction piece (and any coincident one)
                b = breaks[index]                # between pieces b and b + 1
                pc = self._side(seg, j, b, pieces[j])
                if pc != pieces[j]:
                    seg.switch(j, pc)
                self._switches(seg, j)

    def _work_left(self) -> int | None:
        """Block-steps left before a work bound (max_work of the event, max_run_work of the run), or None."""
        left = [b - done for b, done in ((self.max_work, self.ev["block_steps"]), (self.max_run_work, self.run_work))
                if b is not None]
        return min(left) if left else None

    def _over_work(self, steps: int, k: int) -> str:
        if self.max_run_work is not None and self.run_work >= self.max_run_work - k:
            bound = f"the run's bound of {self.max_run_work:.3g} block-steps ran out"
        else:
            bound = f"did not end within {self.max_work:.3g} block-steps"
        return (f"event at t = {float(self.t):.17g} {bound} (Taylor steps × window width; {steps} steps, "
                f"the window at {k} blocks)")

    def _stops(self, seg: _Segment, j: int) -> int:
        """Stop block j (its stop event fired) and every other slipping block of the window whose
        velocity is ≤ 0 at this instant; return how many stopped.

        Blocks of a symmetric chain (a uniform start, equal loads) stop at the same instant to rounding.
        heyoka reports one of the coincident events; a root that lies at or before the next step's start
        shows no sign change in that step, so its stop would be missed and the block would slide
        backwards (tests/test_chain.py, test_equal_stresses_fail_together). A block with σ ≥ 1 at V = 0
        (only at rounding level) cannot stick and keeps slipping from V = 0."""
        wi, p = seg.wi, seg.p
        state, pars, v0 = wi.state, wi.pars, wi.layout.v0
        v = state[seg.velocities].tolist()
        done = 0
        for i in [j] + [i for i in range(seg.k) if i != j and p[i] and v[i] <= 0]:
            state[v0 + i] = 0
            if seg.load(i) >= 0:   # σ_i ≥ 1 at V = 0 (only at rounding level): it cannot stick
                self.counts["overloaded"] += 1
                continue
            p[i] = 0.0
            pars[wi.params.at("p", i)] = 0
            seg.stopped.append(seg.idx[i])
            done += 1
        return done

    def _side(self, seg: _Segment, j: int, b: int, pc: int) -> int:
        """The piece of block j at breakpoint b (x_j = b to rounding): b + 1 if x_j is rising there, b if
        falling (σ_j − Φ(b) > 0 or < 0; Φ is continuous), ``pc`` unchanged at a tangency.

        Decided by the direction, not by toggling the piece or by the side of b that x_j rounds to: at
        a crossing x_j lands within an ulp of b on either side, and a block switched at one report was
        flipped back at the next coincident one (a pair of blocks of the three-piece law then slid at
        Φ = 0 below x = 1.5: potency 0.5 % high; tests/test_chain_adversarial.py)."""
        rate = seg.load(j) + self._g_break[b] / seg.nu
        return b + 1 if rate > 0 else b if rate < 0 else pc

    def _switches(self, seg: _Segment, j: int) -> None:
        """After block j switched piece: switch every other slipping block whose x = νv/ν_f already lies
        outside its piece's interval and moves away from it (a crossing at the same instant to rounding,
        missed otherwise as in ``_stops``). A block not yet across, or exactly at a breakpoint, stays:
        heyoka reports its root in the next step (seen at x = b exactly: the crossing came a second
        time). A block just outside but moving back in (switched at this instant, x rounded past b)
        stays too (``_side``)."""
        lower, upper = self._bounds
        p, pieces, nu, nu_f = seg.p, seg.pieces, seg.nu, seg.nu_f
        v = seg.wi.state[seg.velocities].tolist()
        for i in range(seg.k):
            if i != j and p[i]:
                x = (nu * v[i]) / nu_f
                if self._drop_on:                  # the law's argument x/(1 − σ) (its breakpoints)
                    x = x / self._drop_c
                pc = pieces[i]
                if x < lower[pc] or x > upper[pc]:
                    new = self.law.piece_index(x)
                    if abs(new - pc) == 1:         # across one breakpoint: which way is it going?
                        new = self._side(seg, i, min(new, pc), pc)
                    if new != pc:
                        seg.switch(i, new)

    def _back_slip(self, idx):
        """An error message if a slipping block moves backwards (a stop event was missed), else None.
        Every slipping block is in the window (``idx``, the error names it)."""
        if not self._v or min(self._v.values()) >= 0:
            return None
        low, j = min((x, j) for j, x in self._v.items())
        if low < -1e-9 * max(1.0, max(abs(x) for x in self._v.values())):
            return (f"back-slip: block {j} has velocity {float(self.nu * low):.3g} < 0 at t = "
                    f"{float(self.t):.17g} without a stop event")
        return None

    def _commit(self, seg: _Segment) -> None:
        """Fold the segment's scaled increments into the global state (exact up to rounding).

        Only the window's blocks moved, and their Laplacian is the window's own coupling (a block of
        the window next to one outside it is stuck, w = 0), so the stress of block j changes by
        ν(ℓ²·coupling_j − w_j + τ) in the window and by ντ elsewhere: O(M) work plus one O(N) add.
        ``seg.sg`` holds the window's stresses at the segment's start."""
        wi, idx, at, sg, p, pieces, bond, selfc = (seg.wi, seg.idx, seg.at, seg.sg, seg.p, seg.pieces,
                                                   seg.bond, seg.selfc)
        nu, l2, tau, m, k = seg.nu, seg.l2, seg.ta.time, seg.m, seg.k
        st = wi.state.tolist()
        w = st[wi.layout.slips(m)]
        # the window holds every slipping block: their velocities are the state's, the rest are stuck
        v0 = wi.layout.v0
        self._v = {j: st[v0 + i] for i, j in enumerate(idx) if p[i]}
        self._slip.difference_update(seg.stopped)
        if wi.n_pieces > 1:
            pcd = self._pc
            for i, j in enumerate(idx):
                if j in pcd:
                    pcd[j] = pieces[i]
        if self.energy:
            self._energy(wi, idx, np.array(w, dtype=self.dtype), tau)
        sigma = self.sigma
        sigma += nu * tau                       # every block: ντ (the window's are overwritten below)
        new = []
        ud, u, f = self._u, self.u, self._scalar
        sb = self._sblock if self._vth is not None else None
        for i in range(k):
            coupling = bond[i - 1] * w[i - 1] + bond[i] * w[(i + 1) % m] + (selfc[i] - 2) * w[i]
            new.append(sg[i] + nu * ((l2 * coupling - w[i]) + tau))
            j = idx[i]
            ud[j] = (ud[j] if j in ud else f(u[j])) + nu * w[i]
            if sb is not None and j in sb:
                sb[j] += nu * w[i]
        sigma[at] = new
        # the blocks that may be at σ ≥ 1 now (``_segments`` starts them): the window's, unless the
        # largest stress outside it reached 1 too (then every block is scanned)
        far = self._sigma_far
        self._due = None if far is not None and far + nu * tau >= 1 else \
            sorted(j for j, x in zip(idx, new) if x >= 1)
        self.ev["potency"] += nu * self._sum(w[:k])
        self.ev["duration"] += tau
        self.ev["vmax"] = max(self.ev["vmax"], wi.recorder.vmax)
        if self._vth is not None:
            vpos, vb = wi.recorder.vpos, self._vblock
            for i, j in enumerate(idx):
                if j in vb and vpos[i] > vb[j]:
                    vb[j] = vpos[i]
        self.t += tau

    def _energy(self, wi, idx, w, tau) -> None:
        """The segment's driver work, friction dissipation and change of elastic energy (tests)."""
        nu, state, m, k = self.nu, wi.state, wi.m, len(idx)
        dw = np.zeros(self.n, dtype=self.dtype)
        dw[idx] = w[:k]
        dy = nu * (tau - dw)
        db = nu * self._bonds(dw)
        self.ev["elastic"] += np.sum(self.y * dy + dy * dy / 2) + \
            self.l2 * np.sum(self.bond * db + db * db / 2)
        unscale = m / self.dtype(ENERGY_SCALE)
        self.ev["work"] += nu * (np.sum(self.y) * tau + nu * self.n * tau * tau / 2
                                 - nu * state[wi.layout.disp] * unscale)
        self.ev["diss"] += nu * state[wi.layout.diss] * unscale
        self.y += dy
        self.bond += db
