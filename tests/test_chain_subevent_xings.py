"""V_th crossings recorded on the step's dense output without cutting the step (``_compiled._xings``,
``_subevents.run_subevents``; docs/chain.md, "Split in time").

References: an mpmath solution (25 digits, mpmath's own Taylor ODE solver, no engine code) of a block
slipping alone between stuck neighbours, whose V_th crossings and the slip between them give the
threshold event exactly; and the engine's own run in one call (a segment can now close several events,
the surplus is handed out by the next ``run``)."""

import mpmath as mp
import numpy as np
import pytest

from bifurcation.laws import resolve_law
from bifurcation.models.chain._compiled import CompiledChain
from bifurcation.models.chain._subevents import SubeventRun
from bifurcation.models.chain._validate import check_initial

pytestmark = pytest.mark.slow     # compiles the threshold loop (~15 s of CPU on a cold numba cache)

LAW = resolve_law("carlson-langer")


def _bisect(fn, a, b):
    fa = fn(a)
    for _ in range(75):                     # 2^-75 of a 0.05 bracket: 1e-24, below the 25 digits' needs
        c = (a + b) / 2
        if (fn(c) > 0) == (fa > 0):
            a, fa = c, fn(c)
        else:
            b = c
    return (a + b) / 2


def test_a_lone_block_threshold_event_against_mpmath():
    # N = 64, ℓ = 1, ν = 1e-4, ν_f = 0.3, σ_f = 0.01: the first event is block 2 alone (its neighbours stay
    # stuck), so x'' = 1 + ν t − (1 + 2ℓ²) x − (1 − σ_f)/(1 + x'/(ν_f (1 − σ_f))) from rest at stress 1.
    # V_th = half its largest velocity: one threshold event, crossing up and down inside Taylor steps
    n, ell, nu, nu_f, sig = 64, 1.0, 1e-4, 0.3, 0.01
    u = check_initial(n, ell, "free", None, 0.1, 1)
    ref = CompiledChain(LAW, n, ell, nu, nu_f, "free", u.copy(), sigma=sig, lone=False).run(1)["catalog"]
    assert ref["n_blocks"][0] == 1 and ref["hypocentre"][0] == 2
    mp.mp.dps = 25
    NU, NF, S, K = mp.mpf(nu), mp.mpf(nu_f), mp.mpf(sig), mp.mpf(1 + 2 * ell ** 2)
    f = mp.odefun(lambda t, y: [y[1], 1 + NU * t - K * y[0] - (1 - S) / (1 + y[1] / (NF * (1 - S)))], 0,
                  [mp.mpf(0), mp.mpf(0)])
    vth = 0.5 * float(ref["max_velocity"][0])
    grid = [mp.mpf(i) / 20 for i in range(52)]          # the event lasts 2.63 (the catalog's duration)
    vg = [f(t)[1] - vth for t in grid]
    iu = next(q for q in range(51) if vg[q] <= 0 < vg[q + 1])
    idn = next(q for q in range(iu + 1, 51) if vg[q] > 0 >= vg[q + 1])
    tu = _bisect(lambda t: f(t)[1] - vth, grid[iu], grid[iu + 1])
    td = _bisect(lambda t: f(t)[1] - vth, grid[idn], grid[idn + 1])
    run = SubeventRun(LAW, n, ell, nu, nu_f, "free", u.copy(), v_threshold=vth, sigma=sig)
    got = run.run(1)["catalog"]
    assert got["hypocentre"].tolist() == [2] and got["n_blocks"].tolist() == [1]
    # measured: t_start −1.9e-13 (t ≈ 1e4, its ulp 1.8e-12), duration 1.4e-12, potency 5.7e-13 relative; the
    # bounds are ~10x the Taylor method's tolerance 1e-11 (a crossing misplaced by a step would be ~1e-2 off)
    assert abs(float(got["t_start"][0] - ref["t_start"][0] - tu)) < 1e-10
    assert abs(float(got["duration"][0] - (td - tu))) < 1e-10
    assert abs(float(got["potency"][0] / (f(td)[0] - f(tu)[0]) - 1)) < 1e-10
    # the slip before V_th and after it, counted apart: x(t_up) + (x(stop) − x(t_down)), the stop's slip
    # being the all-stuck catalog's potency
    below = f(tu)[0] + (mp.mpf(float(ref["potency"][0])) - f(td)[0])
    assert abs(float(run.totals[1] / below - 1)) < 1e-9


def test_events_closed_in_one_segment_come_out_one_call_at_a_time():
    # ℓ = 10, ν = 0.01, σ_f = 0.01 (the carlson-langer-1991 preset's chain, N = 300): many crossings per
    # segment; 1-event calls hand out a segment's surplus in order and equal one call, bit for bit
    n = 300
    u = check_initial(n, 10.0, "free", None, 0.1, 1)
    kw = dict(v_threshold=1e-3, sigma=0.01)
    one = SubeventRun(LAW, n, 10.0, 0.01, 0.2, "free", u.copy(), **kw).run(300)["catalog"]
    run = SubeventRun(LAW, n, 10.0, 0.01, 0.2, "free", u.copy(), **kw)
    parts, surplus = [], 0
    while sum(p["potency"].size for p in parts) < 300:
        parts.append(run.run(1)["catalog"])
        surplus = max(surplus, run._pending["potency"].size)
    assert surplus > 0                       # some segment did close more than one event
    cat = {k: np.concatenate([p[k] for p in parts]) for k in one}
    for k in one:
        assert np.array_equal(cat[k], one[k]), k
    assert np.all(np.diff(cat["t_start"]) > 0)
    assert np.all(cat["duration"] > 0)


def test_the_rk4_baseline_reads_the_same_lone_threshold_event():
    # the bench's numba RK4 (``_bench_rk4.rk4_vth``: friction drop, one-way friction, V_th read at step ends)
    # from the same start at dt = 1e-3: the event of the test above (reference: the engine's, checked against
    # mpmath there) with each crossing read up to one step late, so duration within 2 dt, potency within 1e-3
    from bifurcation.models.chain._bench_rk4 import rk4_vth

    n, ell, nu, nu_f, sig = 64, 1.0, 1e-4, 0.3, 0.01
    u = check_initial(n, ell, "free", None, 0.1, 1)
    ref = CompiledChain(LAW, n, ell, nu, nu_f, "free", u.copy(), sigma=sig, lone=False).run(1)["catalog"]
    vth = 0.5 * float(ref["max_velocity"][0])
    exact = SubeventRun(LAW, n, ell, nu, nu_f, "free", u.copy(), v_threshold=vth, sigma=sig).run(1)["catalog"]
    out, tot = np.zeros((5, 4)), np.zeros(3)
    t_end = float(ref["t_start"][0] + ref["duration"][0]) + 1.0
    ne, _ = rk4_vth(0, ell * ell, nu, nu_f, sig, False, u.copy(), np.zeros(n), 0.0, t_end, vth, 1e-3, 20, out, tot)
    assert ne == 1 and int(out[3, 0]) == 2 and int(out[4, 0]) == 1
    assert abs(out[2, 0] - exact["duration"][0]) < 2e-3
    assert abs(out[1, 0] / exact["potency"][0] - 1) < 1e-3
