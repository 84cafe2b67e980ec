"""The compiled chain engine's Taylor method for the Carlson–Langer law (``_compiled._taylor``): against the
same engine with DOP853 steps and against the exact heyoka engine, event by event."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from bifurcation.laws import resolve_law
from bifurcation.models.chain._compiled import CompiledChain, run_verified
from bifurcation.models.chain._validate import check_initial

#: the issue's bound for ``--verify`` (issue 18); the Taylor method at the default tol 1e-11 measured
#: ≤ 2.9e-13 in the bench (N = 64 … 4096) and ≤ 4.1e-12 on 60 random Carlson–Langer chains (k = 5000–5299)
VERIFY_BOUND = 1e-10
DATA = Path(__file__).parent / "data"


def test_taylor_is_used_for_carlson_langer_only():
    u0 = np.zeros(4)
    assert CompiledChain(resolve_law("carlson-langer"), 4, 1.0, 1e-3, 0.2, "free", u0).taylor
    assert not CompiledChain(resolve_law("carlson-langer"), 4, 1.0, 1e-3, 0.2, "free", u0, taylor=False).taylor
    assert not CompiledChain(resolve_law("exponential"), 4, 1.0, 1e-3, 0.2, "free", u0).taylor


def test_taylor_and_dop853_steps_give_the_same_catalog():
    """40 events with Taylor and with DOP853 steps from the same start: equal sizes and hypocentres,
    potencies within 1e-9 (both ~1e-12 from the exact engine; the chain's chaos amplifies differences
    over the run), and the Taylor method in under half the steps (measured 13 against 36 per event at
    N = 64, ν = 1e-4)."""
    law = resolve_law("carlson-langer")
    u0 = check_initial(32, 1.0, "free", None, 0.1, 3)
    a = CompiledChain(law, 32, 1.0, 1e-3, 0.2, "free", u0).run(40)
    b = CompiledChain(law, 32, 1.0, 1e-3, 0.2, "free", u0, taylor=False).run(40)
    assert a["status"] == b["status"] == 1
    a, b = a["catalog"], b["catalog"]
    assert list(a["n_blocks"]) == list(b["n_blocks"]) and list(a["hypocentre"]) == list(b["hypocentre"])
    np.testing.assert_allclose(a["potency"], b["potency"], rtol=1e-9)
    assert np.sum(a["steps"]) < 0.5 * np.sum(b["steps"])
    assert np.all(a["error_estimate"] < 1e-9)     # the series' last term: measured ≤ 1e-13


@pytest.mark.parametrize("n, nu, nu_f, ends, sigma", [
    (64, 1e-4, 0.2, "free", 0.0),      # the bench's case
    (6, 1e-3, 0.3, "periodic", 0.9),   # a large friction drop: the series' amplitude (1 − σ_f)
    (1, 1e-3, 0.3, "free", 0.0),       # one block (after its lone trajectory: none)
])
def test_taylor_events_equal_the_exact_engine(n, nu, nu_f, ends, sigma):
    """Every event of a 24-event run re-run by the heyoka engine from the same pre-event state: same
    hypocentre and size; times, potencies, durations and velocity maxima within 1e-10."""
    law = resolve_law("carlson-langer")
    u0 = check_initial(n, 1.0, ends, None, 0.1, 1)
    out, rep = run_verified(CompiledChain(law, n, 1.0, nu, nu_f, ends, u0, sigma=sigma, lone=False), 24, 1.0)
    assert out["status"] == 1 and rep["checked"] == 24
    assert rep["mismatched"] == []
    assert rep["largest_any"] <= VERIFY_BOUND, rep["largest"]


def test_a_block_at_rest_that_rises_and_falls_back_stops_past_its_excursion():
    """A stored pre-event state (tests/data/chain_taylor_rest_stop.json, how it was made is noted there)
    whose event keeps a block slipping at V = 0 that rises and falls back inside one step: it ran to
    max_steps (no-stop) before the stop was looked for past the excursion; now it completes as the exact
    engine's event (measured 5.1e-11 in duration, DOP853 2.8e-11: v reaches 0 there with a small slope)."""
    d = json.loads((DATA / "chain_taylor_rest_stop.json").read_text())
    law = resolve_law("carlson-langer")
    for taylor in (True, False):
        run = CompiledChain(law, d["n"], 1.0, 1e-4, 0.2, "free", np.zeros(d["n"]), taylor=taylor, max_steps=20_000)
        run.restore(np.array(d["sigma"]), np.array(d["u"]), d["t"])
        out, rep = run_verified(run, 1, 1.0)
        assert out["status"] == 1, (taylor, out["message"])
        assert rep["mismatched"] == [] and rep["largest_any"] <= VERIFY_BOUND, (taylor, rep["largest"])


def _window_with_row(coeffs, v0=1.0):
    """A Taylor window whose slot 0 has the dense output v(θ) = v0 + Σ_k coeffs[k − 1] θ^k."""
    run = CompiledChain(resolve_law("carlson-langer"), 4, 1.0, 1e-3, 0.2, "free", np.zeros(4))
    win = run._win
    win.fv[0, :] = 0.0
    win.fv[0, :len(coeffs)] = coeffs
    win.v[0] = v0
    return win


def test_velocity_maximum_on_a_taylor_step_is_the_polynomials():
    """``_vmax_at`` on a Taylor step (Newton on the slope since this session; golden section and an Illinois
    root before): the closed form of a parabola v0 + aθ − bθ², maximum v0 + a²/(4b) at θ = a/(2b), to
    rounding in v (Newton stops at |Δθ| ≤ 1e-10, which moves v by b·1e-20); on an order-20 polynomial the
    value at the root in (0, 1) of its derivative found by numpy (companion-matrix eigenvalues, independent
    of the engine's Horner and Newton), to 4 ulps."""
    from bifurcation.models.chain._compiled import _vmax_at

    a, b, v0 = 3.0, 2.0, 1.5
    vm, th = _vmax_at(0, _window_with_row([a, -b], v0), 1.0)
    assert abs(th - a / (2 * b)) < 1e-9
    assert abs(vm - (v0 + a * a / (4 * b))) <= 4e-16 * vm
    rng = np.random.default_rng(7)
    c = np.concatenate(([2.0, -1.0], rng.normal(0.0, 0.3, 18) / np.arange(3, 21) ** 2))
    poly = np.polynomial.Polynomial(np.concatenate(([0.7], c)))
    crit = [r.real for r in poly.deriv().roots() if abs(r.imag) < 1e-12 and 0.0 < r.real < 1.0]
    assert len(crit) == 1                                  # one interior maximum: the Newton branch
    vm, th = _vmax_at(0, _window_with_row(c, 0.7), 1.0)
    assert abs(th - crit[0]) < 1e-9
    assert abs(vm - poly(crit[0])) <= 4 * 2.2e-16 * vm


def test_velocity_maximum_before_the_peak_is_the_value_at_the_cut():
    """A step cut (at an event) before v peaks: v rises over [0, lim], so the largest v is v(lim) exactly
    (golden section converged to within 1e-12 of lim, a part in ~1e-12 low)."""
    from bifurcation.models.chain._compiled import _vmax_at

    a, b, v0, lim = 3.0, 2.0, 1.5, 0.5          # peak at 0.75
    vm, th = _vmax_at(0, _window_with_row([a, -b], v0), lim)
    assert th == lim and vm == v0 + a * lim - b * lim * lim
