"""Burridge–Knopoff chains against a second independent reference, at parameters no other test uses.

Reference: tests/_xref_chain.py, mpmath.odefun on the whole chain in absolute time (30 digits), no code
of the package nor of tests/_indep_chain.py. u0 = −0.3/(1 + 4ℓ²) · default_rng(seed).random(N) (all
blocks stuck at t = 0), passed to both.

Cases: σ = 0.2 (periodic, ℓ = 3; free, piecewise-linear across its kink at ν_f = 0.49; periodic, a
three-piece user formula), σ = 0 (free, ℓ = 0.5, ν_f = 0.07, a rational formula; periodic N = 2,
exponential). Three events each (the reference takes 25–190 s per case). Measured when written
(AVX2): hypocentres and sizes identical; t_start, potency, duration, max velocity within 1.5e-14
(double) and 1.3e-16 (quad) of the reference.

Tolerances: docs/chain.md ("Friction drop σ") states ≤ 2.3e-13 over the first 10 events against its
own reference in double; quad results are real128 rounded to a double, 1e-15 allows a few roundings
and the chain's amplification of its ~1e-33 error.
"""

from __future__ import annotations

import numpy as np
import pytest
from mpmath import mpf

import bifurcation as bf

import _xref_chain as ref
from _indep_sample import sample

CASES = [   # the default sample (cases 0 and 4) holds two σ = 0.2 ones, 25–45 s each; the σ = 0 cases
            # (odd indices) take 160–190 s each for their slow creeping starts: BIFURCATION_INDEP=all
    dict(law="carlson-langer", n=3, ends="periodic", ell=3.0, nu=1e-3, nu_f=0.31, sigma=0.2, seed=5),
    dict(law="1/(1+x+x^2)", n=4, ends="free", ell=0.5, nu=1e-4, nu_f=0.07, sigma=0.0, seed=6),
    dict(law="piecewise(1 - x, 0.5, 0.5 - (x - 0.5)/5, 2, 0.2)", n=3, ends="periodic", ell=1.0, nu=2e-3,
         nu_f=0.15, sigma=0.2, seed=9),
    dict(law="exponential", n=2, ends="periodic", ell=1.3, nu=3e-3, nu_f=0.2, sigma=0.0, seed=8),
    dict(law="piecewise-linear", n=3, ends="free", ell=2.0, nu=1e-2, nu_f=0.49, sigma=0.2, seed=7),
]
FIELDS = ("t_start", "potency", "duration", "max_velocity")
TOL = {"double": 2.3e-13, "quad": 1e-15}
EVENTS = 3


@pytest.mark.slow
@pytest.mark.parametrize("case", sample(CASES, 4))
def test_chain_against_odefun(case):
    cs = dict(case)
    seed = cs.pop("seed")
    u0 = [float(x) for x in -0.3 / (1 + 4 * cs["ell"] ** 2) * np.random.default_rng(seed).random(cs["n"])]
    expected = ref.chain_events(cs["law"], u0, ell=cs["ell"], nu=cs["nu"], nu_f=cs["nu_f"], sigma=cs["sigma"],
                                ends=cs["ends"], events=EVENTS)
    for precision in ("double", "quad"):
        r = bf.chain(cs["law"], n=cs["n"], ell=cs["ell"], nu=cs["nu"], nu_f=cs["nu_f"], sigma=cs["sigma"],
                     ends=cs["ends"], u0=u0, events=EVENTS, precision=precision)
        for i, e in enumerate(expected):
            assert int(r.hypocentre[i]) == e["hypocentre"] and int(r.n_blocks[i]) == e["n_blocks"], (precision, i)
            for k in FIELDS:
                rel = abs(mpf(float(getattr(r, k)[i])) - e[k]) / abs(e[k])
                assert rel <= TOL[precision], (precision, i, k, float(rel))
