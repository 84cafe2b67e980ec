"""The quasi-dynamic rate-and-state chain's first event against a second independent reference.

Reference: tests/_xref_rate_state.py, rs_chain_first_event — the equations of docs/rs-chain.md (M = 0,
η > 0) in (V_j, θ_j, P) by mpmath.odefun at 25 digits, threshold crossings and velocity maxima refined by
findroot; no code of the package nor of tests/_indep_rs_chain.py. The start is the engine's, recomputed
here: ln V_j = ln V_lp + A r_j, r = default_rng(seed).uniform(−1, 1, N), θ_j at steady state.

Case (untested elsewhere): aging, N = 3 periodic, a = 0.008, b = 0.0135, Dc = 0.02, k = 0.12 (the
damped slider's k_c is (b − a − ηV_lp)/Dc = 0.225), ℓ = 0.9, η = 1e-3, v_th = 4, A = 0.5, seed 3.
Measured when written: t_start 8.7e-16, potency 2.7e-15, duration 9.7e-17, max velocity 4.3e-15
relative; docs/rs-chain.md states its own 40-digit reference agrees to 2.5e-14, the bound here.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from mpmath import mpf

from bifurcation.models.rs_chain import rs_chain

import _xref_rate_state as ref


@pytest.mark.slow
def test_first_event_against_odefun():
    kw = dict(state_law="aging", a=0.008, b=0.0135, dc=0.02, k=0.12, ell=0.9, v_lp=1.0, eta=1e-3, v_th=4.0,
              periodic=True)
    n, amplitude, seed = 3, 0.5, 3
    r = rs_chain(n=n, amplitude=amplitude, seed=seed, events=1, **kw)
    x0 = math.log(kw["v_lp"]) + amplitude * np.random.default_rng(seed).uniform(-1.0, 1.0, n)
    y0 = [math.log(kw["dc"] / kw["v_lp"])] * n
    e = ref.rs_chain_first_event("aging", list(x0), y0, a=kw["a"], b=kw["b"], dc=kw["dc"], k=kw["k"],
                                 ell=kw["ell"], v_lp=kw["v_lp"], eta=kw["eta"], v_th=kw["v_th"], periodic=True)
    assert int(r.hypocentre[0]) == e["hypocentre"] and int(r.n_blocks[0]) == e["n_blocks"]
    for field in ("t_start", "potency", "duration", "max_velocity"):
        rel = abs(mpf(float(getattr(r, field)[0])) - e[field]) / abs(e[field])
        assert rel <= 2.5e-14, (field, float(rel))
