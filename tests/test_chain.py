"""The chain engine against closed forms, the single-block engine, energy, and an independent reference.

Reference values: ``bifurcation.slip`` (the single-block engine, itself tested against exact mpmath
solutions in test_precision.py), the mpmath Taylor reference ``bifurcation.models.chain.reference``
(shares no code with the engine) live on small cases and through the golden catalogs of
tests/data/chain_golden.json (written by tests/chain_golden_gen.py), and energy conservation.
"""

from __future__ import annotations

import json
from pathlib import Path

import mpmath
import numpy as np
import pytest

import bifurcation as bf
from bifurcation.laws import resolve_law
from bifurcation.models.chain import ChainStatus, chain
from bifurcation.models.chain._loop import ChainLoop
from bifurcation.models.chain._validate import check_initial
from bifurcation.models.chain.reference import reference_chain

GOLDEN = json.loads((Path(__file__).parent / "data" / "chain_golden.json").read_text())


@pytest.mark.parametrize("law", ["carlson-langer", "piecewise-linear", "exponential"])
@pytest.mark.parametrize("nu", [1e-2, 1e-6, 1e-12])
@pytest.mark.parametrize("nu_f", [0.3, 0.45, 0.7])
def test_one_block_is_the_single_block_engine(law, nu, nu_f):
    """N = 1: every event is the single block's cycle: potency Δ, recurrence Δ/ν.

    Tolerance 1e-14: both engines integrate the same scaled equation with the same tolerance; the
    single-block engine's own error near ν_f = 1/2 reaches 1.1e-14 (docs/engine.md, Precision).
    """
    one = bf.slip(law, nu=nu, nu_f=nu_f)
    r = chain(law, n=1, ell=1.0, nu=nu, nu_f=nu_f, u0=[0.0], events=3)
    assert r.status == ChainStatus.COMPLETE
    delta = float(one.delta)
    assert np.all(np.abs(r.potency / delta - 1) <= 1e-14)
    assert np.all(np.abs(r.max_velocity / float(one.max_velocity) - 1) <= 1e-14)
    assert np.all(np.abs(r.duration / float(one.stop_time) - 1) <= 1e-14)
    # from u = 0 the first failure is at t = 1/ν, then every Δ/ν (T = Δ/ν exactly, Eq. 5)
    # (relative to t itself: the time is one float64 sum, so differences of it are not that precise)
    assert np.allclose(r.t_start, (1 + np.arange(3) * delta) / nu, rtol=1e-14, atol=0)


@pytest.mark.parametrize("ends", ["free", "periodic"])
def test_uncoupled_blocks_are_independent(ends):
    """ℓ = 0: N independent single blocks. Each event is one block slipping Δ; block j fails first at
    (1 − σ_j(0))/ν = (1 + u_j)/ν and then every Δ/ν."""
    nu, nu_f = 1e-6, 0.3
    u0 = np.array([-0.1, -0.35, 0.0, -0.2, -0.05])
    r = chain("carlson-langer", n=5, ell=0.0, nu=nu, nu_f=nu_f, ends=ends, u0=u0, events=15)
    delta = float(bf.slip("carlson-langer", nu=nu, nu_f=nu_f).delta)
    assert np.all(r.n_blocks == 1)
    assert np.all(np.abs(r.potency / delta - 1) <= 1e-14)
    first_fail = (1 + u0) / nu
    expected = np.sort(np.concatenate([first_fail + k * delta / nu for k in range(3)]))
    order = np.argsort(np.concatenate([first_fail + k * delta / nu for k in range(3)]), kind="stable")
    assert np.allclose(r.t_start, expected, rtol=1e-14, atol=0)
    assert list(r.hypocentre) == list(np.tile(np.arange(5), 3)[order])


# piecewise-linear is slow: its energy integrators (M = 1..16) serve this test alone, ~2.7 s of CPU to
# compile on an empty heyoka cache; energy across switch events stays in the fast suite through the
# three-piece law of tests/test_chain_adversarial.py::test_energy_balance_for_formula_laws
@pytest.mark.parametrize("law", ["carlson-langer", pytest.param("piecewise-linear", marks=pytest.mark.slow)])
@pytest.mark.parametrize("ends", ["free", "periodic"])
@pytest.mark.parametrize("nu", [pytest.param(1e-2, marks=pytest.mark.slow),   # 2-3 s each: long events
                                1e-6, 1e-10])
def test_energy_balance_per_event(law, ends, nu):
    """Driver work − friction dissipation = change of elastic energy, per event, to 1e-12 relative
    (of the dissipation): the budget is integrated along the trajectory, so it fails if the motion does
    not satisfy the equations (kinetic energy is zero at both ends of an event)."""
    r = chain(law, n=16, ell=1.0, nu=nu, nu_f=0.25, ends=ends, amplitude=0.1, seed=2, events=60, energy=True)
    assert r.n_blocks.max() > 3          # multi-block events are in the sample
    mismatch = r["driver_work"] - r["dissipation"] - r["elastic_change"]
    assert np.all(np.abs(mismatch) <= 1e-12 * np.abs(r["dissipation"]))


def _golden_cases():
    return [pytest.param(c, id=f"{c['law']}-{c['n']}-{c['ends']}-{c['nu']:g}") for c in GOLDEN["cases"]]


@pytest.mark.parametrize("case", _golden_cases())
def test_double_against_golden_reference(case):
    """24 events of small chains against the mpmath reference (36 digits): hypocentres and sizes
    identical; times and potencies to 1e-12, or to 100× the event's sensitivity to a 1-ulp change of
    one initial displacement where the chain's chaos makes that larger (the golden file records it per
    event; it reaches 2e-7 by event 24 of the 4-block case). 100×: that sensitivity is one rounding,
    an event makes one per step and block (measured ratios 2–50). In quad precision the engine meets
    1e-25 on the same cases (test below)."""
    u0 = [float(x) for x in case["u0"]]
    r = chain(case["law"], n=case["n"], ell=case["ell"], nu=case["nu"], nu_f=case["nu_f"], ends=case["ends"],
              u0=u0, events=GOLDEN["events"])
    assert list(r.hypocentre) == case["hypocentre"]
    assert list(r.n_blocks) == case["n_blocks"]
    assert max(case["n_blocks"]) >= 3
    for key in ("t_start", "potency"):
        ref = np.array([float(x) for x in case[key]])
        allowed = 1e-12 + 100 * np.array(case["ulp_sensitivity"][key])
        assert np.all(np.abs(r[key] / ref - 1) <= allowed), key


@pytest.mark.parametrize("case", [GOLDEN["cases"][i] for i in (1, 3)],
                         ids=["carlson-langer-5-periodic", "piecewise-linear-4-free"])
def test_quad_against_golden_reference(case):
    """In real128 the engine follows the reference through all 24 events to 1e-25 (times, potencies):
    the chaotic amplification (≤ 1e-12 per ulp of double, see the golden file) leaves 1e-34 · 1e12."""
    law = resolve_law(case["law"])
    loop = ChainLoop(law, case["n"], case["ell"], case["nu"], case["nu_f"], case["ends"],
                     np.array([float(x) for x in case["u0"]]), precision="quad")
    cat = loop.run(GOLDEN["events"])["catalog"]
    assert cat["hypocentre"] == case["hypocentre"] and cat["n_blocks"] == case["n_blocks"]
    with mpmath.workdps(40):
        for key in ("t_start", "potency", "duration", "max_velocity"):
            err = max(abs(mpmath.mpf(str(a)) / mpmath.mpf(b) - 1) for a, b in zip(cat[key], case[key]))
            assert err <= mpmath.mpf("1e-25"), (key, err)


def test_live_reference_small_chain():
    """A fast live check against the mpmath reference: 3 blocks, periodic, piecewise-linear (switches
    exercised), ν = 1e-3. Same events, times and potencies to 1e-13 (1-ulp sensitivity here < 1e-15)."""
    kw = dict(n=3, ell=1.0, nu=1e-3, nu_f=0.3, ends="periodic")
    r = chain("piecewise-linear", amplitude=0.1, seed=4, events=6, **kw)
    ref = reference_chain("piecewise-linear", u0=r.u0, events=6, dps=32, order=30, **kw)
    assert list(r.hypocentre) == ref["hypocentre"] and list(r.n_blocks) == ref["n_blocks"]
    assert max(ref["n_blocks"]) >= 2
    assert float(max(ref["max_velocity"])) > kw["nu_f"]     # the kink of Eq. (12) was crossed
    for key in ("t_start", "potency", "duration", "max_velocity"):
        assert max(abs(float(a / b - 1)) for a, b in zip(r[key], ref[key])) <= 1e-13, key


# N = 12 and 16: the windows (M = 4..16) and whole chains are those the σ = 0 golden runs of
# tests/test_chain_sigma.py compile for these laws, so an empty heyoka cache compiles little anew
# (at N = 24 the whole chain and M = 32 were this test's alone); every path is still taken
@pytest.mark.parametrize("law,ends,n", [("piecewise-linear", "periodic", 12), ("carlson-langer", "free", 16)])
def test_windows_equal_whole_chain(law, ends, n):
    """Integrating only the window of slipping blocks (with far failures in closed form) gives the same
    catalog as integrating the whole chain every event: identical events, and times and potencies to
    1e-12 over the first events (before the chain's chaos amplifies the rounding of the two orders of
    summation; it grows ~10× per large event, see test_double_against_golden_reference)."""
    u = check_initial(n, 1.0, ends, None, 0.3, 7)
    runs = []
    for full in (False, True):
        loop = ChainLoop(resolve_law(law), n, 1.0, 1e-2, 0.3, ends, u, full_window=full)
        runs.append((loop.run(12)["catalog"], loop.counts))
    (win, counts), (whole, _) = runs
    assert counts["grow"] > 0 and counts["far"] > 0 and counts["window"] > 0   # every path taken
    assert win["hypocentre"] == whole["hypocentre"] and win["n_blocks"] == whole["n_blocks"]
    for key in ("t_start", "potency"):
        assert np.allclose(win[key], whole[key], rtol=1e-12, atol=0), key


def test_a_spanning_slip_pulse_keeps_a_narrow_window():
    """The window holds the blocks slipping now and their neighbours, not every block the event has
    touched: event 1 of this 48-block chain slips all 48 blocks as a pulse, and no window holds half
    of them (10 measured when written). The same two events integrated over the whole chain agree to
    1e-12 (the check of test_windows_equal_whole_chain, here on a system-spanning event)."""
    u = check_initial(48, 1.0, "free", None, 0.1, 1)
    runs = []
    for full in (False, True):
        loop = ChainLoop(resolve_law("carlson-langer"), 48, 1.0, 1e-3, 0.2, "free", u, full_window=full)
        runs.append((loop.run(2)["catalog"], loop.widest))
    (win, widest), (whole, widest_full) = runs
    assert win["n_blocks"][1] == 48 and widest_full[1] == 48
    assert widest[1] < 24
    assert win["hypocentre"] == whole["hypocentre"] and win["n_blocks"] == whole["n_blocks"]
    for key in ("t_start", "potency", "duration", "max_velocity"):
        assert np.allclose(win[key], whole[key], rtol=1e-12, atol=0), key


def test_small_nu_double_matches_quad():
    """ν = 1e-12, a 6-block periodic chain: double against quad to 1e-14 (per-segment scaled variables
    keep relative precision; the single-block engine's own figure near the threshold is 1.1e-14, and
    the 1-block events here have stiffness 1 + 2ℓ² = 3, ν_f = 0.3 just above 1/(2√3))."""
    kw = dict(n=6, ell=1.0, nu=1e-12, nu_f=0.3, amplitude=0.1, seed=5, events=5, ends="periodic")
    rd = chain("piecewise-linear", **kw)
    rq = chain("piecewise-linear", precision="quad", **kw)
    assert list(rd.hypocentre) == list(rq.hypocentre)
    for key in ("t_start", "potency", "duration"):
        assert np.all(np.abs(rd[key] / rq[key] - 1) <= 1e-14), key


def test_final_state_and_catalog_consistent():
    """The final displacements minus the initial ones sum to the total potency; all stresses < 1."""
    r = chain("carlson-langer", n=32, ell=2.0, nu=1e-4, nu_f=0.3, amplitude=0.1, seed=1, events=100)
    assert abs(np.sum(r.u - r.u0) / np.sum(r.potency) - 1) <= 1e-12
    assert np.all(r.stress < 1)
    assert r.events == 100 and r.status == ChainStatus.COMPLETE
    assert np.all(np.diff(r.t_start) > 0) and np.all(r.n_blocks >= 1)


def test_event_bound_gives_status():
    """An event that cannot end within max_steps gives status no-stop, a message, and a catalog of the
    events that did end."""
    r = chain("carlson-langer", n=8, ell=1.0, nu=1e-2, nu_f=0.3, amplitude=0.1, seed=3, events=5, max_steps=50)
    assert r.status == ChainStatus.NO_STOP and "max_steps" in r.message
    assert r.events < 5


@pytest.mark.parametrize("law", ["carlson-langer", "piecewise-linear", "exponential"])
@pytest.mark.parametrize("nu", [1e-3, 1e-9])
@pytest.mark.parametrize("nu_f", [0.2, 0.25, 0.35])
def test_lone_block_is_a_rescaled_single_block(law, nu, nu_f):
    """A block slipping alone among stuck neighbours has stiffness k = 1 + 2ℓ²; rescaling time by √k and
    displacement by k maps it exactly onto the single block with ν/√k and √k·ν_f (docs/chain.md,
    "Threshold"): P = Δ(ν/√k, √k ν_f)/k. Tolerance 1e-14: rounding of the two rescaled parameters
    (d ln Δ/d ln ν_f is ~10 here, far from the threshold 1/(2√3) ≈ 0.2887)."""
    ell, k = 1.0, 3.0
    u0 = np.zeros(9)
    u0[4] = -0.3                                   # the centre block is the most loaded
    r = chain(law, n=9, ell=ell, nu=nu, nu_f=nu_f, u0=u0, events=1)
    assert r.hypocentre[0] == 4 and r.n_blocks[0] == 1
    single = bf.slip(law, nu=nu / np.sqrt(k), nu_f=nu_f * np.sqrt(k))
    assert abs(r.potency[0] / (float(single.delta) / k) - 1) <= 1e-14


@pytest.mark.parametrize("law", ["carlson-langer", "piecewise-linear"])
@pytest.mark.parametrize("ends", ["free", "periodic"])
def test_a_uniform_chain_slides_as_one_block(law, ends):
    """Ties: from a uniform start every block fails at t = 1/ν, switches friction piece and stops at
    the same instants (heyoka reports one of coincident events; the engine must handle the others), and
    the chain slides as one single block (the Laplacian of a uniform U vanishes), event after event:
    P = N·Δ(ν, ν_f) of the single-block engine. Tolerance 1e-13: two engines at ~1e-16 each over three
    events. The engine once missed the coincident stops and let 10 of 12 blocks slide backwards
    (status no-stop); without the coincident switches the piecewise-linear chain turns non-finite.
    (Not for the three-piece law of the next test: its uniform slide is unstable, rounding differences
    between blocks grow to O(1) within the first event, as physics says they should.)"""
    nu, nu_f, n = 1e-3, 0.2, 12
    r = chain(law, n=n, ell=1.0, nu=nu, nu_f=nu_f, u0=np.zeros(n), ends=ends, events=3)
    assert r.status == ChainStatus.COMPLETE, r.message
    assert list(r.n_blocks) == [n] * 3 and r.hypocentre[0] == 0
    delta = float(bf.slip(law, nu=nu, nu_f=nu_f).delta)
    assert np.max(np.abs(r.potency / (n * delta) - 1)) <= 1e-13


@pytest.mark.parametrize("law", ["carlson-langer", "piecewise-linear", "piecewise(1 - x, 0.5, 0.75 - x/2, 1.5, 0)"])
@pytest.mark.parametrize("ends", ["free", "periodic"])
def test_two_equal_loads_far_apart_fail_together(law, ends):
    """Two equally loaded blocks far apart (σ = 0.9 both, computed by the same formula, so equal to the
    last bit) fail at the same instant: one event of two lone blocks, P = 2·Δ(ν/√3, √3 ν_f)/3
    (docs/chain.md, "Threshold"). Tolerance 1e-14 as in the lone-block test above."""
    nu, nu_f, n = 1e-3, 0.2, 12
    u0 = np.zeros(n)
    u0[3] = u0[8] = -0.3                           # σ_3 = σ_8 = 0.9, every other block ≤ 0
    r = chain(law, n=n, ell=1.0, nu=nu, nu_f=nu_f, u0=u0, ends=ends, events=1)
    lone = float(bf.slip(law, nu=nu / np.sqrt(3), nu_f=nu_f * np.sqrt(3)).delta) / 3
    assert r.hypocentre[0] == 3 and r.n_blocks[0] == 2
    assert abs(r.potency[0] / (2 * lone) - 1) <= 1e-14


def test_the_back_slip_guard_names_the_block_and_ignores_rounding():
    """The guard against a missed stop (ChainLoop._back_slip, checked after every segment): a slipping
    block with V < 0 beyond rounding (1e-9 of the largest |v|, its documented allowance) is an error
    that names the block; a negative velocity at rounding level is not. No engine run reaches it
    (every test above completes), so the guard is checked on a hand-set state."""
    loop = ChainLoop(resolve_law("carlson-langer"), 8, 1.0, 1e-3, 0.2, "free", np.zeros(8))
    loop._v = {3: -1.0, 5: 2.0}
    message = loop._back_slip([3, 4, 5])
    assert message.startswith("back-slip: block 3 has velocity -0.001 < 0")
    loop._v = {3: -1e-12, 5: 2.0}
    assert loop._back_slip([3, 4, 5]) is None
    loop._v = {}
    assert loop._back_slip([]) is None
