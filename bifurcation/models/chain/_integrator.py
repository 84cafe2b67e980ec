"""Compiled Taylor integrators for a *window*: M positions holding any set of blocks of the chain.

Scaled, per-segment variables (docs/chain.md): at the start of a segment (time t_s) every block j of
the window has its stress σ_j(t_s) and its displacement is written U_j = U_j(t_s) + ν w_j, V_j = ν v_j,
τ = t − t_s, so that

    (σ_j − 1)/ν = d_j/ν + ℓ²(coupling) − w_j + τ,      d_j = σ_j(t_s) − 1,
    ẇ_j = p_j v_j,   v̇_j = p_j [(σ_j − 1)/ν + g(ν v_j/ν_f)/ν],         g = 1 − Φ,

p_j = 1 for a slipping block and 0 for a stuck one (a runtime parameter, flipped at events). The
window holds the blocks that slipped in the event *and their chain neighbours*; every other block
is stuck for the whole segment (w = 0). Position i of the window is coupled to positions i ± 1
(mod M) through runtime bond parameters b_i ∈ {0, 1} (1 where the two blocks are neighbours in the
chain), and to itself through s_i ∈ {0, 1, 2} (the ghosts of free chain ends, U_0 ≡ U_1):

    coupling_i = b_{i−1} w_{i−1} + b_i w_{i+1} + (s_i − 2) w_i.

So one compiled integrator per window size serves any set of clusters anywhere in the chain, free or
periodic. At a segment start w = 0 and every term is as small as the motion itself, so relative
precision holds block by block at any ν (docs/chain.md, "Precision").

Terminal events (all O(1) in the scaled state, exact, never smoothed):
  * per position, one stop/start event ``select(p_i, x_i, −q_i (σ_i − 1)/ν)`` downwards: a slipping
    block stops when x_i = νv_i/ν_f returns to 0, a stuck one starts when σ_i reaches 1 (q_i scales
    the stress to O(1));
  * per position and breakpoint of the law, ``x_i/b − 1`` either way (the piece is switched there).
Non-terminal events record each velocity maximum (dx_i/dt = 0 from above) at its exact time.

Runtime parameters: ν, ν_f, ℓ², then per position p, d, q, b, s and, for laws with K > 1 pieces,
one-hot piece selectors: named slots of ``_layout.WindowParams``, as the state's are of
``_layout.WindowState`` (the builder and the loop share both).

Friction drop σ > 0 (docs/chain.md, "Friction drop"): a separate integrator (``drop=True``) with two
more runtime parameters at the end, σ and c = 1 − σ, and the law Φ_σ(x) = c·Φ(x/c): g_σ(x) = σ + c·g(y),
y = x/c, breakpoints and rungs at y = b. σ = 0 never builds it: the σ = 0 integrator is the unmodified
one, expression for expression, so its catalogs stay bit-identical (tests/test_chain_sigma.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import heyoka as hy
import numpy as np

from ...laws import _fading
from ...engine._integrator import COOLDOWN, fp_info
from ...laws import FrictionLaw
from ._layout import WindowParams, WindowState

__all__ = ["COMPACT_ABOVE", "ENERGY_SCALE", "WindowIntegrator", "window_integrator"]

#: windows up to this size are compiled in heyoka's full (non-compact) mode by default (see ``window_integrator``)
COMPACT_ABOVE = 8
#: the energy integrals are carried as ENERGY_SCALE/M times their value (see ``_build``)
ENERGY_SCALE = 0.1
_CACHE: dict = {}


class VmaxRecorder:
    """Velocity maxima of the blocks of a window, recorded at their exact times by nt-event callbacks."""

    def __init__(self, layout: WindowState) -> None:
        self.layout = layout
        self.vmax = 0.0
        self.d_output = None   # the integrator's dense-output view, set once it exists
        #: per position, its largest velocity so far (only when the loop sets a list here: event
        #: membership by a velocity threshold; None costs nothing)
        self.vpos = None

    def __deepcopy__(self, memo) -> "VmaxRecorder":
        return self  # heyoka deep-copies callbacks; all of them must record here

    def callback(self, j: int):
        slot = self.layout.v0 + j

        def on_max(ta, time, d_sgn) -> None:
            ta.update_d_output(time)
            v = self.d_output[slot]
            if v > self.vmax:
                self.vmax = v
            vpos = self.vpos
            if vpos is not None and v > vpos[j]:
                vpos[j] = v

        on_max.__deepcopy__ = lambda memo: on_max  # type: ignore[attr-defined]
        return on_max


@dataclass(frozen=True)
class WindowIntegrator:
    """A compiled window integrator and the meaning of its terminal events."""

    m: int
    integrator: object
    event_kind: tuple      # per terminal event: "block" (stop or start), "switch" or "rung"
    event_block: tuple     # block index (or -1)
    event_break: tuple     # breakpoint index (or -1)
    n_pieces: int
    energy: bool
    recorder: VmaxRecorder
    dtype: type
    #: writeable views on the integrator's parameters and state (heyoka never reallocates them; taking
    #: a fresh view costs microseconds, and the event loop touches them several times per segment)
    pars: np.ndarray
    state: np.ndarray
    #: the slots of ``pars`` and ``state`` by name (the loop reads and writes them through these)
    params: WindowParams
    layout: WindowState


def _build(law: FrictionLaw, m: int, precision: str, energy: bool, compact: bool,
           drop_on: bool = False) -> WindowIntegrator:
    fp_type, dtype, num = fp_info(precision)
    w = [hy.make_vars(f"w{j}") for j in range(m)]
    v = [hy.make_vars(f"v{j}") for j in range(m)]
    pieces = law.pieces
    k_pieces = len(pieces)
    params = WindowParams(m, k_pieces, drop_on)
    nu, nu_f, l2 = (params.par(name) for name in WindowParams.GLOBALS)
    p, d, q, bond, selfc = (params.group(name) for name in WindowParams.PER_POSITION)
    sel = params.selectors()
    zero, one = num(0), num(1)
    if drop_on:   # σ and c = 1 − σ, after every other parameter (the σ = 0 layout is unchanged)
        s_drop, c_drop = params.par("sigma"), params.par("c")

    def drop(j, x):
        if k_pieces == 1:
            return pieces[0].drop(x, num)
        # select on the one-hot parameter (a piece may be NaN outside its interval; 0·NaN is NaN)
        out = hy.select(sel[-1][j], pieces[-1].drop(x, num), zero)
        for k in range(k_pieces - 2, -1, -1):
            out = hy.select(sel[k][j], pieces[k].drop(x, num), out)
        return out

    rhs_w, rhs_v, events, kinds, blocks, breaks, nt = [], [], [], [], [], [], []
    layout = WindowState(m, energy)
    recorder = VmaxRecorder(layout)
    fp = {"fp_type": fp_type} if fp_type is not None else {}
    cooldown = fp_type(COOLDOWN) if fp_type is not None else COOLDOWN
    neg, anyd = hy.event_direction.negative, hy.event_direction.any
    # friction that fades faster than any power (e^{−x}, e^{−x−x²/2}) is invisible to heyoka's step
    # control once it is below rounding: a step can cross the whole deceleration and stop the block on
    # a polynomial where friction never came back (e^{−x−x²/2} at ν_f = 0.01: P 1.3e-5 off in double
    # and quad). The single block's rungs (laws._fading, docs/engine.md) end a step at each x_k
    # crossed downward; laws that do not fade have none and pay nothing.
    rungs = _fading.ladder(law, precision).rungs
    diss_terms, disp_terms = [], []
    for j in range(m):
        coupling = bond[j - 1] * w[j - 1] + bond[j] * w[(j + 1) % m] + (selfc[j] - num(2)) * w[j]
        load = l2 * coupling - w[j] + hy.time          # (σ_j − 1)/ν − d_j/ν
        x = (nu * v[j]) / nu_f
        if drop_on:
            y = x / c_drop          # the law's own argument: Φ_σ(x) = c Φ(x/c)
            g = s_drop + c_drop * drop(j, y)
        else:
            y = x
            g = drop(j, x)
        rhs_w.append(hy.select(p[j], v[j], zero))
        rhs_v.append(hy.select(p[j], d[j] / nu + load + g / nu, zero))
        events.append(hy.t_event(hy.select(p[j], x, -q[j] * (d[j] / nu + load)), direction=neg,
                                 cooldown=cooldown, **fp))
        kinds.append("block"), blocks.append(j), breaks.append(-1)
        for b_index, b in enumerate(law.breakpoints):
            events.append(hy.t_event(y / num(b) - one, direction=anyd, cooldown=cooldown, **fp))
            kinds.append("switch"), blocks.append(j), breaks.append(b_index)
        for r in rungs:
            events.append(hy.t_event(y / num(r) - one, direction=neg, cooldown=cooldown, **fp))
            kinds.append("rung"), blocks.append(j), breaks.append(-1)
        # dx/dt·ν_f = σ_j − 1 + g, O(1) for a slipping block: zero from above at a velocity maximum.
        # A stuck position has no maxima and gets −1: heyoka scales its error tolerance with the size of
        # the event functions too, and σ_j − 1 of a stuck block far below threshold (or of a padding
        # position, −1e3) loosened the steps of the whole window (a lone block's potency was off by
        # 9e-9 next to neighbours at σ = −4e10; tests/test_chain_adversarial.py)
        nt.append(hy.nt_event(hy.select(p[j], d[j] + nu * load + g, -one), recorder.callback(j),
                              direction=neg, **fp))
        if energy:
            diss_terms.append(hy.select(p[j], (one - g) * v[j], zero))
            disp_terms.append(w[j])
    eqs = [None] * layout.size
    for j in range(m):
        eqs[j], eqs[layout.v0 + j] = (w[j], rhs_w[j]), (v[j], rhs_v[j])
    if energy:
        diss, disp = hy.make_vars("diss", "disp")
        # heyoka controls the error against the largest state component: unscaled, these integrals
        # (~10·M times a velocity or displacement) loosened the steps for every block, and a stop
        # was missed. ENERGY_SCALE/M keeps them of the size of one block's variables.
        c = num(ENERGY_SCALE / m)
        eqs[layout.diss], eqs[layout.disp] = (diss, c * hy.sum(diss_terms)), (disp, c * hy.sum(disp_terms))
    ta = hy.taylor_adaptive(eqs, np.zeros(layout.size, dtype=dtype), pars=np.zeros(params.size, dtype=dtype),
                            t_events=events, nt_events=nt, compact_mode=compact, **fp)
    recorder.d_output = ta.d_output
    return WindowIntegrator(m, ta, tuple(kinds), tuple(blocks), tuple(breaks), k_pieces, energy, recorder, dtype,
                            ta.pars, ta.state, params, layout)


def window_integrator(law: FrictionLaw, m: int, precision: str = "double", energy: bool = False,
                      compact_above: int = COMPACT_ABOVE, drop: bool = False) -> WindowIntegrator:
    """The cached integrator for a window of ``m`` blocks (compiled on first use in this process).

    Compact mode above M = ``compact_above`` (and always in quad). The full mode's steps are 2-3×
    faster (measured on the chain, Carlson-Langer, double: 9 against 34 µs per step at M = 16, 55
    against 112 at M = 32), but its compile time explodes with M: 18-22 s at M = 16 and 76 s at M = 32
    for the piecewise-linear and exponential laws, 155 s for Carlson-Langer at M = 64, against
    0.1-1.5 s in compact mode up to M = 1024. ``drop``: the integrator of a friction drop σ > 0 (σ and
    1 − σ are its last two parameters). heyoka keeps compiled code in its on-disk cache
    (~/.cache/heyoka), so the price is paid once per machine, law and M: worth it for long runs
    (``bifurcation bench --suite chain`` uses 32), not for a test suite that touches many laws.
    """
    # a fading law's rungs multiply the event equations by up to ~17 (exponential: 16 rungs): full mode
    # then took 13 s to compile at M = 8 (measured), so such laws use it only up to M = 2
    fading = bool(_fading.ladder(law, precision).rungs)
    compact = m > (min(compact_above, 2) if fading else compact_above) or precision != "double"
    key = (law.name, law.formula, m, precision, energy, compact) + (("drop",) if drop else ())
    hit = _CACHE.get(key)
    if hit is None:
        hit = _CACHE[key] = _build(law, m, precision, energy, compact, drop)
    return hit
