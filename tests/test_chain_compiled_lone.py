"""The compiled engine's stored lone-block trajectory (bifurcation/models/chain/_lone.py) against the exact
heyoka engine: events that end on it, hand-overs to DOP853 at a neighbour's or a far block's start, and
a neighbour that starts just before the lone block sticks."""

from __future__ import annotations

import numpy as np
import pytest

from bifurcation.laws import resolve_law
from bifurcation.models.chain._compiled import CompiledChain
from bifurcation.models.chain._loop import ChainLoop

FIELDS = ("t_start", "potency", "duration", "max_velocity")
#: an event that ends on the stored trajectory: heyoka's own Taylor polynomials at tolerance 2.2e-16 (the
#: exact engine's integrator at M = 1; measured 0 to 3e-16 relative against the exact engine's M = 4
#: window); 1e-13 is the bound the engine documents (docs/chain.md, "Engines")
LONE_BOUND = 1e-13
#: a hand-over: DOP853 at tol 1e-11 after it (as tests/test_chain_compiled.py)
HANDOVER_BOUND = 1e-10


def _one_event(law, sigma_field, *, nu=1e-4, nu_f=0.2, ends="free", sigma=0.0, lone=True):
    n = len(sigma_field)
    s = np.asarray(sigma_field, dtype=float)
    run = CompiledChain(resolve_law(law), n, 1.0, nu, nu_f, ends, np.zeros(n), sigma=sigma, lone=lone)
    run.restore(s, np.zeros(n), 0.0)
    got = run.run(1)
    loop = ChainLoop(resolve_law(law), n, 1.0, nu, nu_f, ends, np.zeros(n), drop=sigma)
    loop.sigma[:] = s
    loop.t = np.float64(0.0)
    ref = loop.run(1)
    assert got["status"] == 1 and ref["status"] == 1
    return got["catalog"], ref["catalog"]


def _largest(c, r):
    assert c["hypocentre"][0] == r["hypocentre"][0] and c["n_blocks"][0] == r["n_blocks"][0]
    return max(abs(float(c[f][0]) - float(r[f][0])) / max(1.0, abs(float(r[f][0]))) for f in FIELDS)


@pytest.mark.parametrize("law, ends, sigma, field", [
    ("carlson-langer", "free", 0.0, [0.3, 0.2, 0.9, 0.1, 0.2]),        # interior
    ("carlson-langer", "free", 0.0, [0.9, 0.2, 0.5, 0.1, 0.2]),        # free end (k = ℓ² + 1)
    ("carlson-langer", "periodic", 0.0, [0.3, 0.2, 0.1, 0.2, 0.9]),    # periodic, the hypocentre at the seam
    ("carlson-langer", "free", 0.3, [0.3, 0.2, 0.9, 0.1, 0.2]),        # friction drop σ > 0
    ("carlson-langer", "free", 0.0, [0.9]),                             # N = 1 (k = 1)
    # the tape's loop: slow (the fast suite compiles the Carlson–Langer loop only, tests/test_chain_compiled.py)
    pytest.param("piecewise-linear", "free", 0.0, [0.3, 0.2, 0.9, 0.1, 0.2], marks=pytest.mark.slow),  # switches
    pytest.param("exponential", "free", 0.2, [0.3, 0.2, 0.9, 0.1, 0.2], marks=pytest.mark.slow),  # fading (rungs)
])
def test_a_lone_event_is_the_exact_engines(law, ends, sigma, field):
    """A size-1 event runs no DOP853 step and equals the exact engine's to ≤ 1e-13."""
    nu_f = 0.3 if law == "piecewise-linear" else 0.2      # Φ = 0 above x = 1: the switch is crossed
    c, r = _one_event(law, field, ends=ends, sigma=sigma, nu_f=nu_f)
    assert c["n_blocks"][0] == 1 and c["steps"][0] == 0
    assert _largest(c, r) <= LONE_BOUND
    if law == "piecewise-linear":
        assert c["max_velocity"][0] / nu_f > 1.0
    assert 0 < c["error_estimate"][0] < 1e-13


def test_a_velocity_maximum_at_the_end_of_a_stored_step():
    """σ = 0.01, ν = 0.01, a free end: the lone trajectory's velocity maximum lies in the last 1/64 of
    its step 15 (at 0.9965 of it), where a search of 65 samples finds the step's end largest; the
    engine's max_velocity was then 2.2e-7 (relative) below the exact engine's."""
    c, r = _one_event("carlson-langer", [0.9, 0.2], nu=1e-2, sigma=0.01)
    assert c["n_blocks"][0] == 1 and c["steps"][0] == 0
    assert _largest(c, r) <= LONE_BOUND


@pytest.mark.parametrize("sigma", [0.0, 0.3])
def test_hand_over_at_a_neighbours_start(sigma):
    """The neighbour starts on the stored trajectory (a root on its polynomial); DOP853 continues."""
    c, r = _one_event("carlson-langer", [0.3, 0.2, 0.9, 0.8, 0.2], sigma=sigma)
    assert c["n_blocks"][0] >= 2 and c["steps"][0] > 0
    assert _largest(c, r) <= HANDOVER_BOUND


def test_hand_over_at_a_far_start_next_door():
    """A far block starts while the lone block slips (τ_far = 0.5 < its stop, ~3.9) with one stuck block
    between the two (its load has two moving neighbours): hand-over to DOP853."""
    c, r = _one_event("carlson-langer", [0.2, 0.9 - 5e-5, 0.1, 0.9, 0.1, 0.2], nu=1e-4)
    assert c["n_blocks"][0] == 2 and c["steps"][0] > 0
    assert _largest(c, r) <= HANDOVER_BOUND


@pytest.mark.parametrize("sigma", [0.0, 0.3])
def test_two_lone_blocks_far_apart(sigma):
    """A far block starts 0.5 after the hypocentre, two stuck blocks between their neighbourhoods: both
    follow the stored trajectory from their own starts (no DOP853 step). ν = 1e-3: the far start's time
    is known to ~ε/ν absolute in either engine (their stresses differ by rounding), 2e-13 here."""
    c, r = _one_event("carlson-langer", [0.2, 0.9 - 5e-4, 0.1, 0.1, 0.9, 0.1, 0.2], nu=1e-3, sigma=sigma)
    assert c["n_blocks"][0] == 2 and c["steps"][0] == 0
    assert _largest(c, r) <= 1e-12


def test_a_neighbour_starts_just_before_the_stop():
    """Adversarial: the neighbour's threshold set 1e-7 (in (σ − 1)/ν, i.e. ~1e-7 in time) before the lone
    block's stop, and 1e-7 after it. Before: a two-block event whose second block barely moves, as the
    exact engine's; after: a lone event, no DOP853 step."""
    law = resolve_law("carlson-langer")
    nu = 1e-4
    run = CompiledChain(law, 5, 1.0, nu, 0.2, "free", np.zeros(5))
    t_stop, w_stop = run._lone.sc[0, 0], run._lone.sc[0, 1]
    for eps, size in ((1e-7, 2), (-1e-7, 1)):
        # after the jump the hypocentre is at 1 (σ_h = 0.9 → +0.1); the neighbour reaches 1 at τ with
        # d/ν + ℓ² w(τ) + τ = 0, d = σ_n + 0.1 − 1: set it to cross eps before the stop
        d = nu * (-(w_stop + t_stop) + eps)
        c, r = _one_event("carlson-langer", [0.2, 0.1, 0.9, d + 0.9, 0.1])
        assert c["n_blocks"][0] == size and r["n_blocks"][0] == size
        assert _largest(c, r) <= (HANDOVER_BOUND if size == 2 else LONE_BOUND)


def test_lone_path_equals_dop853_throughout_on_a_run():
    """The same 40 events with and without the stored trajectory (DOP853 in every segment): equal sizes
    and hypocentres, potencies within 1e-9 (both ≤ ~1e-11 from the exact engine; the chain's chaos
    amplifies differences over the run)."""
    law = resolve_law("carlson-langer")
    from bifurcation.models.chain._validate import check_initial

    u0 = check_initial(32, 1.0, "free", None, 0.1, 3)
    a = CompiledChain(law, 32, 1.0, 1e-3, 0.2, "free", u0).run(40)["catalog"]
    b = CompiledChain(law, 32, 1.0, 1e-3, 0.2, "free", u0, lone=False).run(40)["catalog"]
    assert list(a["n_blocks"]) == list(b["n_blocks"]) and list(a["hypocentre"]) == list(b["hypocentre"])
    np.testing.assert_allclose(a["potency"], b["potency"], rtol=1e-9)
    assert np.sum(a["steps"]) < 0.8 * np.sum(b["steps"])
